"""The wire: ROS names and QoS, message builders, CDR layouts, state publishers."""
