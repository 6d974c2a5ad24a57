"""Formations and role assignment for the soccer team (numpy and scipy only).

Modules: `delaunay` (formation files and Delaunay interpolation), `scram`
(role assignment, one entry point `scram.assign`), `bottleneck` and
`hungarian` (the matching algorithms underneath), `priority` (prioritized
SCRAM), `marking` (whom to mark and where), `pathcost` (obstacle-aware costs
evaluated lazily), `voting` (agreeing on one mapping), `field` (constants).
"""
