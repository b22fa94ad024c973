"""The motion layer: move(), planning, the motion pipeline, sensors, modes."""
