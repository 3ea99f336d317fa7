"""envs: built on top of teamsim and cognition (later issues fill this package)."""
