"""What a recording keeps: the recorded topics and each message as it arrived, serialized."""

from typing import NamedTuple

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped

from ..interface import POSE_TOPIC, TARGET_TOPIC, TWIST_TOPIC

# The recorded topics (relative: namespaces and remaps apply) and their types, in CSV order.
TOPICS = {TARGET_TOPIC: PointStamped, POSE_TOPIC: PoseStamped, TWIST_TOPIC: TwistStamped}


class Received(NamedTuple):
    """One message as received: topic key, receive time (ns, node clock), serialized CDR."""

    topic: str
    log_time: int
    data: bytes
