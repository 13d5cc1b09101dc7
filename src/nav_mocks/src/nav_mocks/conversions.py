"""Messages <-> nav_mocks core types (OccupancyMap, Scan, (x, y, yaw) poses, plans)."""
import math

import numpy as np
from geometry_msgs.msg import PoseStamped, Transform, TransformStamped
from nav_msgs.msg import MapMetaData, OccupancyGrid, Path
from sim2d.conversions import yaw_quaternion as yaw_to_quaternion
from floorplan.occupancy_map import OccupancyMap

from nav_mocks.scan_rays import Scan


def quaternion_to_yaw(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def pose_from_msg(pose):
    """geometry_msgs/Pose -> (x, y, yaw); a malformed quaternion is a ValueError."""
    q = pose.orientation
    norm = math.sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w)
    if not math.isfinite(norm) or abs(norm - 1.0) > 0.01:
        raise ValueError(f"orientation quaternion has norm {norm:.3f}, expected 1")
    return (pose.position.x, pose.position.y, quaternion_to_yaw(q))


def pose_to_msg(pose, msg):
    """Fill a geometry_msgs/Pose from (x, y, yaw)."""
    msg.position.x, msg.position.y, msg.position.z = pose[0], pose[1], 0.0
    msg.orientation = yaw_to_quaternion(pose[2])
    return msg


def pose_from_transform(transform):
    """geometry_msgs/Transform -> (x, y, yaw)."""
    t = transform.translation
    return (t.x, t.y, quaternion_to_yaw(transform.rotation))


def transform_msg(pose, parent, child, stamp):
    msg = TransformStamped()
    msg.header.stamp, msg.header.frame_id, msg.child_frame_id = stamp, parent, child
    msg.transform = Transform()
    msg.transform.translation.x, msg.transform.translation.y = pose[0], pose[1]
    msg.transform.rotation = yaw_to_quaternion(pose[2])
    return msg


def map_metadata(grid, stamp):
    meta = MapMetaData()
    meta.map_load_time = stamp
    meta.resolution = grid.resolution
    meta.width, meta.height = grid.width, grid.height
    meta.origin = pose_to_msg(grid.origin, meta.origin)
    return meta


def map_to_msg(grid, frame_id, stamp):
    """OccupancyMap -> nav_msgs/OccupancyGrid (row-major from the origin row, as ROS)."""
    msg = OccupancyGrid()
    msg.header.frame_id, msg.header.stamp = frame_id, stamp
    msg.info = map_metadata(grid, stamp)
    msg.data = grid.cells.astype(np.int8).ravel().tolist()
    return msg


def map_from_msg(msg):
    """nav_msgs/OccupancyGrid -> OccupancyMap; a size mismatch is a ValueError."""
    info = msg.info
    if len(msg.data) != info.width * info.height:
        raise ValueError(f"OccupancyGrid has {len(msg.data)} cells, expected "
                         f"{info.width} x {info.height}")
    cells = np.asarray(msg.data, dtype=np.int8).reshape(info.height, info.width)
    origin = pose_from_msg(info.origin)
    return OccupancyMap(cells=cells, resolution=info.resolution, origin=origin)


def scan_from_msg(msg):
    """sensor_msgs/LaserScan -> Scan (angles in the laser frame)."""
    ranges = np.asarray(msg.ranges, dtype=float)
    angles = msg.angle_min + msg.angle_increment * np.arange(len(ranges))
    return Scan(angles=angles, ranges=ranges, range_min=msg.range_min, range_max=msg.range_max)


def path_to_msg(points, frame_id, stamp, goal_yaw=0.0):
    """(N, 2) plan -> nav_msgs/Path; each pose faces the next point, the last the goal yaw."""
    path = Path()
    path.header.frame_id, path.header.stamp = frame_id, stamp
    for i, (x, y) in enumerate(points):
        if i + 1 < len(points):
            yaw = math.atan2(points[i + 1][1] - y, points[i + 1][0] - x)
        else:
            yaw = goal_yaw
        stamped = PoseStamped()
        stamped.header = path.header
        pose_to_msg((x, y, yaw), stamped.pose)
        path.poses.append(stamped)
    return path
