"""Physics of one mechanism: kinematics, workspace, task region, link solids, MuJoCo models, duty
cycle and closed-chain dynamics."""
