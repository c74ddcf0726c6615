"""The theory: the paper's rigid rod slipping on a rough plane, and what follows its first event.

* ``analytic``: the tip accelerations (eq. linode2), the scaled 10-state system
  with the Appendix A coefficients, b, p and the four contact modes;
* ``critical``: every critical value (theta_L, Psi_L, mu_P, mu_L, Psi_1, Psi_2, ...);
* ``slipping``: the desingularised slipping flow (eq. f) to the first event;
* ``capsule``: the same flow with the contact at a capsule's lowest point
  C = A - r K (the geometry of MuJoCo's, Drake's and Bullet's rods);
* ``corollary``: the slipping states that jam (Corollary 4.2);
* ``impact``: the impact without collision at a jam or a GB point
  (``impact.darboux_keller``) and the continuation of the rigid model through
  impacts, sticking and slipping again (``impact.continuation``);
* ``sticking``: the rod pivoting about its stuck tip, and how it lets go;
* ``gb``: the GB manifold b = p = 0, the matrix K and its linearisation;
* ``paper``: every number the paper prints, with its misprints.

Everything here is in the paper's scaled units (section 2.1) and imports no
contact engine.
"""
