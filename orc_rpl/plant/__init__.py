"""What the servos drive: the MuJoCo cell; serial links."""
