"""rviz markers of a plan_view.PlanView: the reward ripple (Fig. 4-6), the next node, the plan."""
from dataclasses import dataclass

import rospy
from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

NAMESPACE_RIPPLE, NAMESPACE_VALUE = "ripple", "ripple_value"
NAMESPACE_NEXT, NAMESPACE_PLAN, NAMESPACE_STOPS = "next_node", "plan", "plan_stops"


@dataclass(frozen=True)
class MarkerStyle:
    min_diameter: float = 0.15   # sphere of a node with no expected reward [m]
    max_diameter: float = 0.9    # sphere of the node with the highest expected reward [m]
    height: float = 0.05         # z of the markers [m]
    text_height: float = 0.25    # [m]
    line_width: float = 0.06     # plan line [m]


def _point(x, y, z):
    return Point(x=float(x), y=float(y), z=float(z))


def _heat(share):
    """Blue (no reward) -> red (the highest on the graph)."""
    return ColorRGBA(r=float(share), g=0.2, b=float(1.0 - share), a=0.8)


def _marker(frame_id, stamp, namespace, marker_id, kind):
    marker = Marker()
    marker.header.frame_id, marker.header.stamp = frame_id, stamp
    marker.ns, marker.id, marker.type, marker.action = namespace, marker_id, kind, Marker.ADD
    marker.pose.orientation.w = 1.0
    return marker


def plan_markers(view, graph, frame_id="map", stamp=None, style=MarkerStyle()):
    """MarkerArray: a sphere per node sized/coloured by its expected reward (smallest/blue at
    the lowest value on the graph, largest/red at the highest) with the value as text, an arrow
    robot node -> next node, the planned route as a line and numbered stops."""
    stamp = stamp or rospy.Time.now()
    array = MarkerArray()
    # first: clear the previous plan's markers (the number of stops changes)
    clear = _marker(frame_id, stamp, NAMESPACE_STOPS, 0, Marker.TEXT_VIEW_FACING)
    clear.action = Marker.DELETEALL
    array.markers.append(clear)
    low = float(view.values.min()) if len(view.values) else 0.0
    spread = float(view.values.max()) - low if len(view.values) else 0.0
    for node, value in enumerate(view.values):
        x, y, _ = graph.poses[node]
        share = (float(value) - low) / spread if spread > 1e-9 else 0.0  # lowest 0, highest 1
        sphere = _marker(frame_id, stamp, NAMESPACE_RIPPLE, node, Marker.SPHERE)
        sphere.pose.position = _point(x, y, style.height)
        diameter = style.min_diameter + share * (style.max_diameter - style.min_diameter)
        sphere.scale.x = sphere.scale.y = sphere.scale.z = diameter
        sphere.color = _heat(share)
        array.markers.append(sphere)
        text = _marker(frame_id, stamp, NAMESPACE_VALUE, node, Marker.TEXT_VIEW_FACING)
        text.pose.position = _point(x, y - 0.45, style.height + 0.3)
        text.scale.z = style.text_height
        text.color = ColorRGBA(r=0.1, g=0.1, b=0.1, a=1.0)
        text.text = f"{graph.names[node]} {value:.2f}"
        array.markers.append(text)
    arrow = _marker(frame_id, stamp, NAMESPACE_NEXT, 0, Marker.ARROW)
    if view.next_node >= 0 and view.next_node != view.robot_node:
        start, end = graph.poses[view.robot_node], graph.poses[view.next_node]
        arrow.points = [_point(start[0], start[1], 0.4), _point(end[0], end[1], 0.4)]
        arrow.scale.x, arrow.scale.y, arrow.scale.z = 0.12, 0.3, 0.3
        arrow.color = ColorRGBA(r=0.1, g=0.8, b=0.1, a=1.0)
    else:
        arrow.action = Marker.DELETE
    array.markers.append(arrow)
    line = _marker(frame_id, stamp, NAMESPACE_PLAN, 0, Marker.LINE_STRIP)
    if len(view.route) > 1:
        line.points = [_point(graph.poses[n][0], graph.poses[n][1], 0.2) for n in view.route]
        line.scale.x = style.line_width
        line.color = ColorRGBA(r=1.0, g=0.6, b=0.0, a=0.9)
    else:
        line.action = Marker.DELETE
    array.markers.append(line)
    for rank, (instruction_id, node) in enumerate(view.stops, start=1):
        label = _marker(frame_id, stamp, NAMESPACE_STOPS, rank, Marker.TEXT_VIEW_FACING)
        x, y, _ = graph.poses[node]
        label.pose.position = _point(x, y + 0.35 * rank, 0.8)
        label.scale.z = style.text_height
        label.color = ColorRGBA(r=0.9, g=0.45, b=0.0, a=1.0)
        label.text = f"{rank}: #{instruction_id}"
        array.markers.append(label)
    return array
