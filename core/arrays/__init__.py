"""Shared array helpers: many polylines in one array (exact batches), shapely geometry
arrays, resampling, ring areas, and connected components. Every other layer uses these."""
