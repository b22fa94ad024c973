"""The logger (submit/update), recordings, export, plots."""

from orc_rpl.signals.logger import Logger
from orc_rpl.signals.recording import Recording

__all__ = ["Logger", "Recording"]
