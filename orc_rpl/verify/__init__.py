"""Many runs at once on a Dask cluster: `orc verify` (every program of a plant) and `orc sweep` (a parameter grid)."""
