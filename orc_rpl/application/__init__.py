"""Registry of primitives, functions and INSTALL kinds; the built-in features; actions."""
