"""Local control: per-joint position/velocity loops with feed-forward; internal signals."""
