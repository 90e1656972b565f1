"""LaserScan and PointCloud2 geometry at full resolution: statistics, sectors, free gaps, approaches."""
