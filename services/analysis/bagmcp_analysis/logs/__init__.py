"""ROS log records: levels of both ROS versions, filters and summaries."""
