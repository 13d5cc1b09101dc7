"""supervision.ros_params: config dataclasses from parameters, on a dict-backed parameter server."""
from dataclasses import dataclass, field
import pytest

from supervision.config_file import ConfigError
from supervision.ros_params import config_from_params, field_paths, refuse_unknown_params


class FakeParams:
    """A parameter server of nested dicts; "~x" resolves to "/node/x" as in node `node`."""

    def __init__(self, tree):
        self.tree = tree
        self.reads = []

    def resolve(self, name):
        return "/node/" + name[1:] if name.startswith("~") else name

    def _lookup(self, name):
        node = self.tree
        for part in [p for p in self.resolve(name).split("/") if p]:
            if not isinstance(node, dict) or part not in node:
                raise KeyError(name)
            node = node[part]
        return node

    def get(self, name):
        self.reads.append(name)
        return self._lookup(name)

    def has(self, name):
        try:
            self._lookup(name)
        except KeyError:
            return False
        return True

    def read(self, cls, namespace="~", **kwargs):
        return config_from_params(cls, namespace, get_param=self.get, has_param=self.has,
                                  resolve_name=self.resolve, **kwargs)


@dataclass(frozen=True)
class Limits:
    low: float = 0.0   # [m]
    high: float = 1.0  # [m]

    def validate(self):
        if self.low > self.high:
            raise ValueError(f"low {self.low} is above high {self.high}")


@dataclass(frozen=True)
class Params:
    graph: str                               # required
    period: float = 0.1                      # [s]
    max_queue: int = 5
    enabled: bool = True
    path: str = ""
    timeout: float | None = None             # [s]; None = wait for ever
    names: tuple = ("a",)
    camera: dict = field(default_factory=lambda: {"fx": 500.0})
    limits: Limits = Limits()

    def check(self):
        if self.period <= 0:
            raise ValueError(f"period must be > 0; got {self.period}")


def test_unset_parameters_keep_the_defaults_and_set_ones_are_coerced():
    params = FakeParams({"node": {"graph": "maps/h.graph.yaml", "period": 1, "max_queue": 7.0,
                                  "enabled": False, "timeout": 3, "names": ["b", "c"]}})
    got = params.read(Params)
    assert got == Params(graph="maps/h.graph.yaml", period=1.0, max_queue=7, enabled=False,
                         timeout=3.0, names=("b", "c"))
    assert type(got.period) is float and type(got.max_queue) is int
    assert type(got.timeout) is float


def test_an_optional_annotation_coerces_to_its_type():
    @dataclass
    class Counted:
        timeout: int | None = None

    assert FakeParams({"node": {"timeout": 2.0}}).read(Counted).timeout == 2
    assert type(FakeParams({"node": {"timeout": 2.0}}).read(Counted).timeout) is int


def test_a_missing_required_parameter_is_a_key_error_naming_it_and_the_hint():
    with pytest.raises(KeyError, match=r"/node/graph is not set \(see x.launch\)"):
        FakeParams({"node": {}}).read(Params, hint=" (see x.launch)")


def test_a_value_of_the_wrong_type_is_a_value_error_naming_the_resolved_parameter():
    for name, value in (("period", "fast"), ("enabled", "false"), ("names", "abc"),
                        ("camera", [1, 2]), ("path", {"a": 1})):
        tree = {"node": {"graph": "g", name: value}}
        with pytest.raises(ValueError, match=f"parameter /node/{name}: "):
            FakeParams(tree).read(Params)


def test_a_refused_config_names_the_namespace_and_the_field():
    with pytest.raises(ValueError, match=r"^/node: period must be > 0; got -1.0$"):
        FakeParams({"node": {"graph": "g", "period": -1}}).read(Params)


def test_a_nested_dataclass_is_read_from_its_sub_namespace_and_validated_there():
    got = FakeParams({"node": {"graph": "g", "limits": {"high": 4}}}).read(Params)
    assert got.limits == Limits(low=0.0, high=4.0)
    with pytest.raises(ValueError, match=r"^/node/limits: low 5.0 is above high 1.0$"):
        FakeParams({"node": {"graph": "g", "limits": {"low": 5}}}).read(Params)


def test_a_nested_dataclass_keeps_a_given_default_where_its_namespace_is_unset():
    given = Limits(low=0.5, high=2.0)
    assert FakeParams({"node": {"graph": "g"}}).read(Params, limits=given).limits is given
    got = FakeParams({"node": {"graph": "g", "limits": {"high": 3.0}}}).read(Params,
                                                                              limits=given)
    assert got.limits == Limits(low=0.5, high=3.0)


def test_a_computed_default_is_used_only_when_the_parameter_is_unset():
    assert FakeParams({"node": {"graph": "g"}}).read(Params, path="/home/r/.ros/x").path \
        == "/home/r/.ros/x"
    assert FakeParams({"node": {"graph": "g", "path": ""}}).read(Params, path="/r/x").path == ""
    with pytest.raises(TypeError, match="no field"):
        FakeParams({"node": {"graph": "g"}}).read(Params, pathh="x")


def test_a_default_supplies_a_required_field():
    assert FakeParams({"node": {}}).read(Params, graph="default.yaml").graph == "default.yaml"


def test_only_the_named_fields_are_read():
    params = FakeParams({"node": {"graph": "g", "period": 0.5, "max_queue": 9}})
    got = params.read(Params, only=("graph", "period"))
    assert (got.period, got.max_queue) == (0.5, 5)
    assert "~max_queue" not in params.reads


def test_a_namespace_without_a_slash_reads_below_it_and_a_dict_default_is_a_fresh_copy():
    params = FakeParams({"costmap": {"graph": "g", "max_queue": 2}})
    got = params.read(Params, "/costmap")
    assert (got.graph, got.max_queue) == ("g", 2)
    got.camera["fx"] = 1.0
    assert params.read(Params, "/costmap").camera == {"fx": 500.0}


def test_a_dataclass_without_annotations_that_resolve_coerces_by_its_defaults():
    @dataclass
    class Loose:
        rate: "UnknownType" = 2.0  # noqa: F821 - deliberately unresolvable

    assert FakeParams({"node": {"rate": 5}}).read(Loose).rate == 5.0
    assert type(FakeParams({"node": {"rate": 5}}).read(Loose).rate) is float


def test_get_param_and_has_param_come_as_a_pair():
    with pytest.raises(TypeError, match="both"):
        config_from_params(Params, get_param=lambda name: None)


def test_the_values_read_are_logged_on_one_line_with_the_unset_ones_as_defaults():
    lines = []
    params = FakeParams({"node": {"graph": "g", "period": 2, "limits": {"high": 4}}})
    params.read(Params, only=("graph", "period", "enabled", "limits"), log=lines.append)
    assert lines == ["/node: parameters graph='g', period=2.0, limits/high=4.0; "
                     "defaults enabled=True, limits/low=0.0"]


def test_a_long_value_is_shortened_in_the_log_line():
    lines = []
    FakeParams({"node": {"graph": "x" * 300}}).read(Params, only=("graph",), log=lines.append)
    assert lines[0].startswith("/node: parameters graph='xxx")
    assert lines[0].endswith("...; defaults none")
    assert len(lines[0]) < 200


def test_a_parameter_no_field_takes_is_refused_with_the_nearest_known_one():
    names = ["/move_base/period", "/move_base/limits/low", "/move_base/supervision/period",
             "/move_base/camera/fx",
             "/move_base/limits/hihg", "/amcl/whatever"]

    def refuse(present):
        refuse_unknown_params({"": Params, "limits": Limits}, "~", names=lambda: present,
                              resolve_name=lambda name: "/move_base/")

    refuse(names[:4])     # every name taken by a field; the Supervisor's own and others' skipped
    with pytest.raises(ConfigError, match=r"^/move_base: unknown key 'limits/hihg' \(did you "
                                          r"mean 'limits/high'\?\)$"):
        refuse(names)
    assert {"limits/high", "period", "camera/"} <= set(field_paths(Params))
