"""tamp_msgs messages <-> perception's core types (verbal: utterances, people; visual:
PerceptionFrame -> FrameView, PersonResult -> ObservedHuman)."""
import numpy as np
import rospy
from tamp_msgs.msg import Detection, ObservedHuman, PerceptionFrame, Skeleton, Utterance

from perception.stt_worker import AudioInput
from perception.verbal_instructions import Person
from perception.visual_pipeline import FrameView, ObjectBox, PersonView


def person_from_msg(msg):
    """tamp_msgs/Human -> Person (name, phone IP, last known place)."""
    return Person(name=msg.name, ip=msg.ip, location=msg.location)


def utterance_to_msg(text, ip, stamp=None):
    msg = Utterance(text=text, ip=ip)
    msg.header.stamp = stamp if stamp is not None else rospy.Time.now()
    return msg


def utterance_time(msg):
    """When the utterance was spoken [s]; now when the sender left the stamp at 0."""
    return rospy.get_time() if msg.header.stamp.is_zero() else msg.header.stamp.to_sec()


def audio_input_from_msg(msg, topic):
    """tamp_msgs/AudioUtterance -> stt_worker.AudioInput (samples and declared rate as sent,
    checked by the worker); a zero stamp becomes now."""
    stamp = msg.header.stamp if not msg.header.stamp.is_zero() else rospy.Time.now()
    return AudioInput(samples=msg.samples, sample_rate=msg.sample_rate, ip=msg.ip, stamp=stamp,
                      origin=f"{msg.ip or 'the microphone'} on {topic}")


def frame_from_msg(msg):
    """tamp_msgs/PerceptionFrame -> FrameView; ValueError on malformed skeletons."""
    frame = FrameView(int(msg.image_width), int(msg.image_height))
    if frame.width == 0 or frame.height == 0:
        raise ValueError(f"perception frame has an empty image size {frame.width}x{frame.height}")
    for det in msg.objects:
        frame.objects.append(ObjectBox(det.label, float(det.confidence), float(det.x),
                                       float(det.y), float(det.width), float(det.height),
                                       float(det.depth)))
    for i, sk in enumerate(msg.skeletons):
        if not (len(sk.x) == len(sk.y) == len(sk.confidence) == len(sk.depth) == 18):
            raise ValueError(f"skeleton {i} does not have 18 keypoints")
        frame.people.append(PersonView(
            np.column_stack([np.asarray(sk.x, float), np.asarray(sk.y, float)]),
            np.asarray(sk.confidence, float), np.asarray(sk.depth, float),
            np.frombuffer(bytes(sk.joint_rgb), dtype=np.uint8).reshape(3, 3)))
    return frame


def observed_to_msg(result, name, doubted_as=""):
    """PersonResult (+ identity, or the doubted one) -> tamp_msgs/ObservedHuman."""
    act = result.activity
    msg = ObservedHuman(name=name, doubted_as=doubted_as, activity=act.activity,
                        posture=act.posture, location=result.place, near_hands=list(act.near_hands),
                        in_eyesight=list(act.in_eyesight), looking_at_hands=act.looking_at_hands)
    if result.shirt is not None:
        msg.shirt_color = result.shirt.reshape(-1).tolist()
    if result.position is not None:
        msg.localised, (msg.x, msg.y) = True, result.position
    ranked = sorted(act.probabilities.items(), key=lambda kv: -kv[1])
    msg.activity_labels = [a for a, _ in ranked]
    msg.activity_probabilities = [float(p) for _, p in ranked]
    return msg


def image_from_msg(msg):
    """sensor_msgs/Image (bgr8 or rgb8) -> BGR uint8 (H, W, 3); ValueError on other encodings."""
    if msg.height == 0 or msg.width == 0:
        raise ValueError(f"image is empty ({msg.width}x{msg.height})")
    if msg.encoding not in ("bgr8", "rgb8"):
        raise ValueError(f"image encoding {msg.encoding!r} not supported (bgr8, rgb8)")
    rows = np.frombuffer(bytes(msg.data), np.uint8).reshape(msg.height, msg.step)
    image = rows[:, :msg.width * 3].reshape(msg.height, msg.width, 3)
    return np.ascontiguousarray(image[:, :, ::-1] if msg.encoding == "rgb8" else image)


def depth_from_msg(msg):
    """sensor_msgs/Image depth (32FC1 [m] or 16UC1 [mm]) -> float (H, W) [m]."""
    kinds = {"32FC1": (np.float32, 1.0), "16UC1": (np.uint16, 0.001)}
    if msg.encoding not in kinds:
        raise ValueError(f"depth encoding {msg.encoding!r} not supported (32FC1, 16UC1)")
    if msg.height == 0 or msg.width == 0:
        raise ValueError(f"depth image is empty ({msg.width}x{msg.height})")
    dtype, scale = kinds[msg.encoding]
    dtype = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    rows = np.frombuffer(bytes(msg.data), np.uint8).reshape(msg.height, msg.step)
    values = rows[:, :msg.width * dtype.itemsize].copy().view(dtype).reshape(msg.height, msg.width)
    return values.astype(float) * scale


def frame_to_msg(frame, header):
    """FrameView -> tamp_msgs/PerceptionFrame (the image front end's output)."""
    msg = PerceptionFrame(header=header, image_width=frame.width, image_height=frame.height)
    for o in frame.objects:
        msg.objects.append(Detection(label=o.label, confidence=o.confidence, x=int(round(o.x)),
                                     y=int(round(o.y)), width=int(round(o.width)),
                                     height=int(round(o.height)), depth=o.depth))
    for p in frame.people:
        pts = np.nan_to_num(np.asarray(p.points, float))
        msg.skeletons.append(Skeleton(x=pts[:, 0].tolist(), y=pts[:, 1].tolist(),
                                      confidence=np.asarray(p.confidence, float).tolist(),
                                      depth=np.asarray(p.depth, float).tolist(),
                                      joint_rgb=np.asarray(p.shirt, np.uint8).reshape(-1).tolist()))
    return msg
