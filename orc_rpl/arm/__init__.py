"""Arm control: Pinocchio model (FK, IK, dynamics), limits, path velocity control."""
