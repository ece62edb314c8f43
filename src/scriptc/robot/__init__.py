"""The robot as the checks and the run time both know it (docs/robot.md, docs/architecture.md):

- `limits.py`  the table of the robot's limits (key, unit, safe default, range, meaning)
- `profile.py` `Profile`, those limits as typed values
- `motion.py`  what the base does with velocity commands under the profile (ramps, the plan
  of a block's moves, the exact kinematics), for the governor, both robots and K003 alike
"""
