"""Back to strokes (paper 3.3): the bi-edge pass, the stroke graph, joining, Bezier
fitting, and the width, pressure and style carried over from the ink."""
