"""bagmcp plotting service: time series, XY, lidar polar, histograms and run comparisons as PNG images."""
