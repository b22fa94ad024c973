"""Arm control, above the servo: the path velocity controller and external axes in one path coordinate."""
