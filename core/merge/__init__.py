"""Agglomeration (paper 3.2): Fourier descriptors, curve-curve pairing, the distance guard,
and the greedy merge loop that records every merge for replay."""
