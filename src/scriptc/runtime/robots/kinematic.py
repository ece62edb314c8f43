"""The kinematic robot: an ideal holonomic base that does exactly what it is told.

The integration is `scriptc.robot.motion.Kinematics` (the static check K003 predicts a block's run
with the same code): between two velocity changes the pose follows an arc in closed form,
integrated exactly over each interval, not in Euler steps. A ramp of the safety governor
(`set_velocity(..., ramp=...)`, `motion.Ramp`) is followed on the 1 ms grid, like the MuJoCo
robot's: the velocity is constant within each millisecond of the ramp and each millisecond is
an exact arc, summed in closed form when the heading does not change during it (no turning,
or turning without translation); otherwise a ramp costs one arc per millisecond of it (a
second at most with the default profile; the governed 10-minute activity of
bench/bench_mujoco.py runs in about 0.25 s).
"""

from __future__ import annotations

from scriptc.robot.motion import Kinematics


class KinematicRobot(Kinematics):
    name = "kinematic"
