"""The base complex (paper 3.1): strokes noded by GEOS into nodes, curves and patches,
the rings of patches as half-edges, and the light state that merges change."""
