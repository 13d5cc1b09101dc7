"""Fill the core config dataclasses from ROS parameters (one parameter per field)."""
import dataclasses

import rospy


def config_from_params(cls, namespace):
    """An instance of dataclass `cls` whose fields are read from `namespace`/<field>.

    Missing parameters keep the dataclass default; a value of the wrong type, or one the
    config's validate() refuses, is a ValueError naming the parameter.
    """
    values = {}
    prefix = namespace if namespace.endswith(("~", "/")) else namespace + "/"
    for field in dataclasses.fields(cls):
        name = prefix + field.name
        if not rospy.has_param(name):
            continue
        value = rospy.get_param(name)
        default = getattr(cls(), field.name)
        try:
            if isinstance(default, bool):
                value = bool(value)
            elif isinstance(default, (int, float)):
                value = type(default)(value)
            elif isinstance(default, tuple):
                value = tuple(value)
        except (TypeError, ValueError) as error:
            raise ValueError(f"parameter {rospy.resolve_name(name)}: {error}") from error
        values[field.name] = value
    config = cls(**values)
    if hasattr(config, "validate"):
        try:
            config.validate()
        except ValueError as error:   # the core names the field; add where it was read
            raise ValueError(f"{rospy.resolve_name(prefix).rstrip('/')}: {error}") from error
    return config
