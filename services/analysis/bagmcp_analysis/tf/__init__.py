"""TF frames: the tree at a time and transforms chained through it (with quaternion math)."""
