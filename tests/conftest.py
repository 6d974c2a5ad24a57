"""Every test process runs BLAS and OpenMP on one thread: pytest-xdist runs one
worker per core, and their thread pools spinning against each other made numpy's
and scipy's small linear algebra (a formation's triangulation, IK) many times slower."""

from optimization.executor import one_thread

one_thread()
