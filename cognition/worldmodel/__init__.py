"""The world model: what a robot believes about the ball, the goals, obstacles and its team.

Built up by the world-model issue; so far :mod:`cognition.worldmodel.messages` (the team
message) is in place.
"""
