"""orc_rpl: the Open Robot Control architecture in Python (language, executive, motion core, pendant)."""

__version__ = "0.1.0"
