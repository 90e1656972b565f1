"""bagmcp analysis service: trajectory, lidar, logs, TF, images and topic statistics over bags."""
