"""Reinforcement-learning environments built on a teamsim match (PettingZoo and Gymnasium).

==========================  ====================================================================
module / id                 content
==========================  ====================================================================
:mod:`envs.soccer_v0`       PettingZoo soccer: ``parallel_env(**kwargs)`` and ``env(**kwargs)``
``teamsim/Striker-v0``      Gymnasium: one striker against a scripted defender and keeper
``teamsim/Keeper-v0``       Gymnasium: one goalkeeper against a scripted attacker
:mod:`envs.core`            the shared machinery (match, policy robots, rewards, rendering)
:mod:`envs.training`        ``teamsim train`` with Stable-Baselines3 (SuperSuit for soccer_v0)
:mod:`envs.evaluation`      ``teamsim evaluate``: a trained policy over seeds, goals for/against
==========================  ====================================================================

Importing :mod:`envs` registers the Gymnasium ids.
"""

from __future__ import annotations

import gymnasium

for _name, _entry in (("Striker-v0", "envs.tasks:StrikerEnv"), ("Keeper-v0", "envs.tasks:KeeperEnv")):
    if f"teamsim/{_name}" not in gymnasium.registry:
        gymnasium.register(id=f"teamsim/{_name}", entry_point=_entry)
