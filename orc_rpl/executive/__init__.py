"""Runs checked programs: scopes, call stack, program pointer, steps, exceptions."""
