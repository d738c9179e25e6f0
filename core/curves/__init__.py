"""The output curves: their Bezier fit and its memo, the ink attributes they carry, the
regions they close."""
