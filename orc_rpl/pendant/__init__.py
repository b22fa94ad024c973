"""The teach pendant: a headless session joining its parts (editor, execution, jogger, pointer, panels) and a thin prompt-toolkit application."""
