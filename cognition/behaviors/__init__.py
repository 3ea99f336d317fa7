"""Behaviors: explicit state machines that turn beliefs into motion requests."""
