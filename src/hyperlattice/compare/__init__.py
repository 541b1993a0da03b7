"""Graph against continuum: measured comparisons through :mod:`hyperlattice.dictionary`.

* :mod:`.levels` - graph and continuum levels side by side, the convergence analysis of the
  relative error (the paper's open question), partition functions and level counting;
* :mod:`.green` - graph Green functions against the continuum (``eq21``);
* :mod:`.correlation` - two-point functions against hyperbolic distance (collapse);
* :mod:`.sums` - lattice sums against integrals (``eq11``), the counting function;
* :mod:`.scaling` - the formal operator :math:`A_h` and its h-expansion toward :math:`\\Delta_g`.
"""
