"""The logger (submit/update), recordings, export, plots."""
