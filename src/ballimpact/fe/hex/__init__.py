"""The hexahedral geometry of the explicit engine: 8-node bricks (`element`), the O-grid ball
and slab meshes (`mesh`) and the kernel with friction and targets (`kernel`)."""
