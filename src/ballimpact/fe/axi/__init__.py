"""The axisymmetric geometry of the explicit engine: quads of a layered ball on its axis
(`element`), their mesh (`mesh`) and the kernel (`kernel`)."""
