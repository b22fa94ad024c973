"""Real equipment behind the motion layer's seams: serial servo buses (Feetech STS, Dynamixel 2.0) and their emulator."""
