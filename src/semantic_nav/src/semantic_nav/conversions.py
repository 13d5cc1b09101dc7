"""Messages <-> semantic_nav core types (the node's only message code)."""
import numpy as np
from geometry_msgs.msg import Point, Twist
from tamp_msgs.msg import FollowDirectionsFeedback, FollowDirectionsResult
from visualization_msgs.msg import Marker

from semantic_nav.laser_layer import model_from_scan


def scan_to_core(msg):
    """sensor_msgs/LaserScan -> (ranges float32 array, laser_layer.LaserModel)."""
    model = model_from_scan(msg.header.frame_id or "laser", msg.angle_min, msg.angle_increment,
                            len(msg.ranges), msg.range_min, msg.range_max)
    return np.asarray(msg.ranges, dtype=np.float32), model


def twist(v, w):
    msg = Twist()
    msg.linear.x, msg.angular.z = float(v), float(w)
    return msg


def feedback_msg(feedback, question=""):
    """follow_session.Feedback (and the question the robot waits on an answer to) ->
    FollowDirectionsFeedback."""
    return FollowDirectionsFeedback(index=feedback.index, current=feedback.text,
                                    instruction_class=feedback.instruction_class,
                                    class_confidence=feedback.confidence,
                                    corners=feedback.corners, question=question)


def result_msg(outcome_or_error, completed=0):
    """Outcome (follow_session) or an error text -> FollowDirectionsResult."""
    if isinstance(outcome_or_error, str):
        return FollowDirectionsResult(success=False, completed=completed,
                                      message=outcome_or_error)
    outcome = outcome_or_error
    return FollowDirectionsResult(success=outcome.status == "succeeded",
                                  completed=outcome.completed, message=outcome.message)


def doorway_marker(points, frame_id, stamp, size):
    """Ends of the beams cut at doorways [(x, y)] (laser frame) -> a POINTS marker (orange,
    `size` m); no points clears it."""
    marker = Marker()
    marker.header.frame_id, marker.header.stamp = frame_id, stamp
    marker.ns, marker.id, marker.type = "semantic_nav_doorways", 0, Marker.POINTS
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.scale.x = marker.scale.y = size
    marker.color.r, marker.color.g, marker.color.a = 1.0, 0.5, 1.0
    marker.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in points]
    return marker


def path_marker(points, frame_id, stamp, width):
    """Driven path [(x, y)] -> a LINE_STRIP marker (green, `width` m; in rviz the laser is red,
    odometry cyan)."""
    marker = Marker()
    marker.header.frame_id, marker.header.stamp = frame_id, stamp
    marker.ns, marker.id, marker.type, marker.action = "semantic_nav_path", 0, Marker.LINE_STRIP, \
        Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.scale.x = width
    marker.color.r, marker.color.g, marker.color.b, marker.color.a = 0.2, 0.9, 0.2, 1.0
    marker.points = [Point(x=float(x), y=float(y), z=0.0) for x, y in points]
    return marker
