"""The robot's brain: field map, vision, localization, world model and behaviors."""
