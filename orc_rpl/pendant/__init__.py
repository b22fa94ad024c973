"""The teach pendant: prompt-toolkit application and rich views; no domain logic."""
