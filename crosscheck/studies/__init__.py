"""Studies that compare any contact engine with the theory, each taking an engine's name.

* ``grids``: starting states (product grids, random slipping states).
* ``agreement``: an engine's first event against the analytic one, state by
  state, at one or more settings of its options (convergence in timestep and
  contact stiffness), with censoring at domain exits and the disagreement
  binned by boundary distance, contact time and off-plane angle.
* ``onset``: the lift-off onset against Psi_L.
* ``jams``: no jam below mu_P; the Corollary 4.2 jams above it.
* ``mujoco_contact``: MuJoCo-only measurements (the force at the capsule
  point, the friction direction).
* ``dynamics_terms``: Pinocchio's M, C, g, J, Delassus against the paper.
* ``validate``: ``crosscheck validate ENGINE``, every check of an engine.

Modules are imported by name; importing this package loads no engine.
"""
