"""Simulation stage: own ship (USV) among target ships, COLREGs encounters and their evaluation."""
