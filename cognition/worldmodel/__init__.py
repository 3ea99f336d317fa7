"""The world model: what a robot believes about the ball, the goals, obstacles and its team.

Built up by the world-model issue. In place so far:

========================================  ================================================
module                                    content
========================================  ================================================
:mod:`cognition.worldmodel.messages`      the team message (58 bytes), checked on receipt
:mod:`cognition.worldmodel.kalman_ball`   functional core of the Darmstadt Kalman ball
:mod:`cognition.worldmodel.ball`          the Kalman ball module (percepts, odometry, team)
:mod:`cognition.worldmodel.hypotheses`    multi-hypothesis ball with CMU's three levels
:mod:`cognition.worldmodel.team`          teammates' reports and the fused team ball
:mod:`cognition.worldmodel.goal`          goal pose from a scan's two posts (CMU IV.B)
:mod:`cognition.worldmodel.obstacles`     occupancy grid and 72-sector obstacles (Darmstadt VII)
========================================  ================================================
"""
