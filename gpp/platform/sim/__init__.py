"""The sim platform: a fast pymunk world where agents stack blocks and navigate.

`SimPlatform` (platform.py) runs on virtual time and serves low-level actions by mapped
name, like ROS action servers: "/stack", "/get_block_pose", "/gripper_home" on the workbench
(workbench.py) and "/navigate_to_frame" on the map (navigation.py); the map also emits
exogenous events ("/battery", region events such as "/victim_detected"). Worlds are TOML data
(world.py, stdlib/worlds/); render.py draws frames for `--record` and `--snapshot`.
"""

from gpp.platform.sim.platform import SimPlatform, SimStats
from gpp.platform.sim.world import World, WorldError

__all__ = ["SimPlatform", "SimStats", "World", "WorldError"]
