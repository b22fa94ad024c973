"""The teach pendant: a headless session (session.py and its mixins) and a thin prompt-toolkit application (app.py)."""
