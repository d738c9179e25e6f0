"""Input and output: sketches read from and written to SVG and ``.scap`` files, and
cleaned into the unit-diagonal frame the pipeline works in (paper 3.1)."""
