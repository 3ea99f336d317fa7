"""Throughput measurements (not tests): run each module as a script."""
