"""The world model: object tree, poses, frames, model/spatial/soft attributes, YAML I/O."""
