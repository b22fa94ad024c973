"""Static rules: names, units, primitive signatures, the FRAME-context rule."""
