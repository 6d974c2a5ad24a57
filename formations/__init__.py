"""Formations and role assignment for the soccer team (numpy, scipy and numba only).

Modules: `delaunay` (formation files and Delaunay interpolation), `scram`
(role assignment, one entry point `scram.assign`), `bottleneck` and
`hungarian` (the matching algorithms underneath; the compiled kernels are in
`_kernels`, `_lsap`, `_bigint`, with `_jit` their numba decorator), `priority` (prioritized
SCRAM), `marking` (whom to mark and where), `pathcost` (obstacle-aware costs
evaluated lazily), `voting` (agreeing on one mapping), `field` (constants).
"""
