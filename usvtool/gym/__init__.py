"""usvtool's scenes as a Gymnasium environment (the ``gym`` extra: ``pip install
'usvtool[gym]'``; docs/gym.md): :class:`UsvEnv`, registered as ``usvtool/Encounter-v0`` when
this package is imported, so that ``gymnasium.make("usvtool/Encounter-v0", family="imazu")``
makes one. Nothing else in usvtool imports this package: usvtool works without gymnasium. The
observation and the command's clip are :mod:`usvtool.sim.observation`'s (gymnasium-free), which
the ``policy`` controller shares.
"""

import gymnasium

from usvtool.gym.env import UsvEnv
from usvtool.gym.reward import Reward

#: The environment's id in gymnasium's registry.
ENV_ID = "usvtool/Encounter-v0"

if ENV_ID not in gymnasium.registry:
    gymnasium.register(id=ENV_ID, entry_point="usvtool.gym.env:UsvEnv")

__all__ = ["ENV_ID", "Reward", "UsvEnv"]
