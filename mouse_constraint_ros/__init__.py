"""ROS 2 node serving one rigid body dragged by a mouse constraint."""
