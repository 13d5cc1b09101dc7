"""Fill a node's config dataclass from ROS parameters: one parameter per field.

    params = config_from_params(NodeParams)                      # ~<field> for every field
    costmap = config_from_params(CostmapConfig, "~costmap")      # ~costmap/<field>
    params = config_from_params(NodeParams, db_path=default_db)  # a computed default

A field without a default is a required parameter (KeyError naming it when unset). A field whose
value is itself a dataclass is read from the sub-namespace of its name (~stt/model_dir) when that
is set, else it keeps its default. Values are coerced to the field's type (its annotation, else
its default's type); a value that does not fit, or that the config's constructor, `check()` or
`validate()` refuses, is a ValueError naming the resolved parameter or namespace.

A node whose parameters come from a file (config/nav_mocks.yaml, loaded with rosparam) calls
`refuse_unknown_params({"": NodeParams, "costmap": CostmapConfig})` after reading them: a
parameter under its namespace that no field takes is refused with the nearest known name, as the
config files are (`supervision.config_file`).

Each call logs the values it read, once, on one INFO line (`/sim2d: parameters speed=2.0, ...;
defaults seed=0, ...`, the unset ones as defaults), so a launch argument that never reached the
node (roslaunch ignores a misspelt `spede:=2`) shows as the value the node runs with.
"""
import dataclasses
import types
import typing

import rospy

from supervision.config_file import ConfigError, unknown_key_message

MISSING = dataclasses.MISSING
SCALARS = (bool, int, float, str)
CONTAINERS = (tuple, list, dict)
SHOWN_CHARS = 120   # longest value the start-up line shows in full


@dataclasses.dataclass(frozen=True)
class ParamSource:
    """Where parameters come from: rospy's functions, or a fake in tests."""

    get: typing.Callable = rospy.get_param
    has: typing.Callable = rospy.has_param
    resolve: typing.Callable = rospy.resolve_name
    log: typing.Callable = rospy.loginfo   # the start-up line of the values read


def config_from_params(cls, namespace="~", *, only=None, hint="", get_param=None,
                       has_param=None, resolve_name=None, log=None, **defaults):
    """An instance of dataclass `cls` read from the parameters `namespace`/<field>.

    Args:
        only: names of the fields read as parameters; the others keep their defaults.
        hint: appended to the KeyError of a missing required parameter (where to set it).
        get_param, has_param, resolve_name: rospy's by default (a fake in tests; resolving
            is then the identity unless given).
        log: takes the line of the values read; rospy.loginfo by default, nothing when
            get_param and has_param are fakes.
        defaults: per-field defaults replacing the dataclass's (computed ones, e.g. under
            ROS_HOME); a parameter that is set still wins.
    """
    if get_param is None and has_param is None:
        source = ParamSource(resolve=resolve_name or rospy.resolve_name,
                             log=log or rospy.loginfo)
    elif get_param is None or has_param is None:
        raise TypeError("config_from_params: give both get_param and has_param, or neither")
    else:
        source = ParamSource(get_param, has_param, resolve_name or str, log or (lambda line: None))
    prefix = namespace if namespace.endswith(("~", "/")) else namespace + "/"
    read = []
    config = _read(cls, prefix, source, only, hint, defaults, read)
    source.log(values_line(source.resolve(prefix).rstrip("/") or "/", read))
    return config


def refuse_unknown_params(layout, namespace="~", *, names=None, resolve_name=None,
                          ignore=("supervision",)):
    """Raise ConfigError for the first parameter under `namespace` that no field takes:
    "/move_base: unknown key 'costmap/robot_raduis' (did you mean 'costmap/robot_radius'?)".

    layout: sub-namespace ("" for the namespace itself) -> the dataclass read there, or a tuple
        of the dataclasses read there.
    names, resolve_name: rospy.get_param_names and rospy.resolve_name by default (fakes in tests).
    ignore: sub-namespaces other code reads (the Supervisor's own parameters).
    """
    resolve = resolve_name or rospy.resolve_name
    root = resolve(namespace).rstrip("/") + "/"
    known = sorted({(f"{sub}/" if sub else "") + name for sub, classes in layout.items()
                    for cls in (classes if isinstance(classes, tuple) else (classes,))
                    for name in field_paths(cls)})
    for full in sorted(names() if names is not None else rospy.get_param_names()):
        if not full.startswith(root):
            continue
        name = full[len(root):]
        if name.split("/")[0] in ignore or name in known or any(
                name.startswith(path) for path in known if path.endswith("/")):
            continue
        raise ConfigError(f"{root.rstrip('/')}: {unknown_key_message(name, known)}")


def field_paths(cls, prefix=""):
    """The parameter names the fields of dataclass `cls` take, nested dataclasses as
    sub-namespaces ("stt/model_dir"); a mapping field takes any name below it ("camera/")."""
    paths = []
    hints = _type_hints(cls)
    for field in dataclasses.fields(cls):
        if not field.init:
            continue
        default = _field_default(field)
        nested = _dataclass_type(hints.get(field.name), default)
        if isinstance(default, dict) or hints.get(field.name) is dict:
            paths.append(f"{prefix}{field.name}/")
        elif nested is None:
            paths.append(prefix + field.name)
        else:
            paths += field_paths(nested, f"{prefix}{field.name}/")
    return paths


def values_line(where, read):
    """`where: parameters a=1, b='x'; defaults c=2.0` of `read`: (name, value, set) each."""
    def shown(entries):
        return ", ".join(f"{name}={_shown(value)}" for name, value, _ in entries) or "none"
    return (f"{where}: parameters {shown([e for e in read if e[2]])}; "
            f"defaults {shown([e for e in read if not e[2]])}")


def _shown(value):
    text = repr(value)
    return text if len(text) <= SHOWN_CHARS else text[:SHOWN_CHARS - 3] + "..."


def _read(cls, prefix, source, only, hint, defaults, read, path=""):
    fields = [f for f in dataclasses.fields(cls) if f.init]
    unknown = set(defaults) - {f.name for f in fields}
    if unknown:
        raise TypeError(f"{cls.__name__} has no field(s) {sorted(unknown)}")
    hints = _type_hints(cls)
    values = {}
    for field in fields:
        name = prefix + field.name
        default = defaults.get(field.name, _field_default(field))
        if only is not None and field.name not in only:
            if default is not MISSING:
                values[field.name] = default
            continue
        nested = _dataclass_type(hints.get(field.name), default)
        if nested is not None and source.has(name):
            base = {} if default is MISSING else _field_values(default)
            values[field.name] = _read(nested, name + "/", source, None, hint, base, read,
                                       f"{path}{field.name}/")
        elif nested is None and source.has(name):
            values[field.name] = _coerce(source.get(name), hints.get(field.name), default,
                                         source.resolve(name))
            read.append((path + field.name, values[field.name], True))
        elif default is not MISSING:
            values[field.name] = default
            read.append((path + field.name, default, False))
        else:
            raise KeyError(f"parameter {source.resolve(name)} is not set{hint}")
    try:
        config = cls(**values)
        for check in ("check", "validate"):
            if callable(getattr(config, check, None)):
                getattr(config, check)()
    except ValueError as error:   # the config names the field; add where it was read
        raise ValueError(f"{source.resolve(prefix).rstrip('/') or '/'}: {error}") from error
    return config


def _field_default(field):
    if field.default is not MISSING:
        return field.default
    if field.default_factory is not MISSING:
        return field.default_factory()
    return MISSING


def _field_values(instance):
    return {f.name: getattr(instance, f.name) for f in dataclasses.fields(instance) if f.init}


def _type_hints(cls):
    try:
        return typing.get_type_hints(cls)
    except Exception:  # noqa: BLE001 - an annotation that does not resolve: use the defaults
        return {}


def _dataclass_type(annotation, default):
    if dataclasses.is_dataclass(default) and not isinstance(default, type):
        return type(default)
    if isinstance(annotation, type) and dataclasses.is_dataclass(annotation):
        return annotation
    return None


def _target_type(annotation, default):
    """The type a parameter's value is coerced to; None = taken as it is."""
    args = typing.get_args(annotation)
    if typing.get_origin(annotation) in (typing.Union, types.UnionType) and type(None) in args:
        rest = [a for a in args if a is not type(None)]
        annotation = rest[0] if len(rest) == 1 else None
    origin = typing.get_origin(annotation) or annotation
    if origin in SCALARS + CONTAINERS:
        return origin
    if default is not MISSING and type(default) in SCALARS + CONTAINERS:
        return type(default)
    return None


def _coerce(value, annotation, default, name):
    """`value` as the field's type; ValueError naming the parameter `name` if it is not one."""
    target = _target_type(annotation, default)
    if value is None or target is None:
        return value
    if target is bool and not isinstance(value, (bool, int, float)):
        raise ValueError(f"parameter {name}: expected a boolean, got {value!r}")
    if target in (tuple, list) and not isinstance(value, (tuple, list)):
        raise ValueError(f"parameter {name}: expected a list, got {value!r}")
    if target is dict and not isinstance(value, dict):
        raise ValueError(f"parameter {name}: expected a dictionary, got {value!r}")
    if target is str and not isinstance(value, (str, int, float)):
        raise ValueError(f"parameter {name}: expected a string, got {value!r}")
    try:
        return target(value)
    except (TypeError, ValueError) as error:
        raise ValueError(f"parameter {name}: {error}") from error
