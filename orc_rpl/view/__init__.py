"""The 3D view in the browser (viser) and videos of runs: reads the cell, the world and the signals, commands nothing."""
