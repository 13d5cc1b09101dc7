"""eval_semnav's command line (tools.eval_semnav over evaluation_run) on the L floor with the
expert as the policy: the table, pictures, plan and JSON it writes, reusing a plan, --first, and
the errors of bad input."""
import json

import pytest
import yaml

from semnav_learning.evaluation import EpisodeOutcome, EpisodeSpec, load_plan
from semnav_learning.evaluation_run import (EvaluationRun, EvaluationRunError,
                                            first_of_each_class, spoken_specs, with_stayed)
from semnav_learning.spoken import Heard, Reading
from semnav_learning.tools.eval_semnav import argument_parser, main
from semnav_l_floor import write_l_floor
from tamp_resources import resource, workspace

ROOT = resource()      # holds config/ and maps/ as the workspace does


@pytest.fixture(scope="module")
def expert_run(tmp_path_factory):
    """One expert episode per applicable class of the L floor, its plan written (40 starts
    sampled: classes 5 to 8 never apply here, and the default 240 only take longer). The
    URG-04LX: the range table of the L floor that test_evaluation and test_recipe use too."""
    folder = tmp_path_factory.mktemp("eval_semnav")
    write_l_floor(folder)
    argv = ["--map", str(folder / "l_floor.yaml"), "--policy", "expert", "--workers", "1",
            "--episodes-per-class", "1", "--candidates", "40", "--laser", "urg04lx",
            "--docs", str(folder / "docs"), "--name", "tiny",
            "--json", str(folder / "tiny.json"), "--plan", str(folder / "plan.json")]
    assert main(argv=argv) == 0
    return folder, argv


def test_a_run_writes_its_plan_table_pictures_and_episodes(expert_run, capsys):
    folder, argv = expert_run
    specs = load_plan(folder / "plan.json")
    classes = sorted({s.labels[-1] for s in specs})
    # an L corridor: straight on, back, the corner's turn and the same side's end turn
    assert {1, 4} <= set(classes) <= {1, 2, 3, 4, 9, 10}
    assert len(specs) == len(classes)               # one episode per class
    result = json.loads((folder / "tiny.json").read_text())
    assert [e["spec"]["labels"] for e in result["episodes"]] == [list(s.labels) for s in specs]
    assert [row[0] for row in result["policy"]["rows"]] == classes
    assert result["policy"]["total"][1] == len(specs)
    assert result["args"]["policy"] == "expert" and "expert" not in result    # no reference
    markdown = (folder / "docs" / "tiny.md").read_text()
    assert markdown.startswith("**tiny** (expert, urg04lx, l_floor, seed 0)")
    assert markdown.rstrip().endswith("`scripts/eval_semnav " + " ".join(argv) + "`")
    assert (folder / "docs" / "tiny_paths.png").stat().st_size > 1000


def test_a_written_plan_is_reused_and_first_keeps_n_per_class(expert_run, tmp_path):
    folder, _ = expert_run
    docs = tmp_path / "docs"
    main(argv=["--plan", str(folder / "plan.json"), "--policy", "expert", "--workers",
                     "1", "--first", "1", "--classes", "1", "--laser", "urg04lx", "--docs",
                     str(docs), "--name", "again", "--json", str(tmp_path / "again.json")])
    again = json.loads((tmp_path / "again.json").read_text())
    first = json.loads((folder / "tiny.json").read_text())
    # the plan's episodes, not a new draw for --classes 1; the expert drives them alike
    assert [e["spec"] for e in again["episodes"]] == [e["spec"] for e in first["episodes"]]
    assert [e["success"] for e in again["episodes"]] == [e["success"] for e in first["episodes"]]


def test_first_of_each_class_keeps_plan_order_within_a_class():
    specs = [EpisodeSpec("f", (float(i), 0.0, 0.0), (label,), "s", False)
             for i, label in enumerate([3, 1, 3, 1, 3, 9])]
    kept = first_of_each_class(specs, 2)
    assert [(s.labels[0], s.start[0]) for s in kept] == [(1, 1.0), (1, 3.0), (3, 0.0),
                                                         (3, 2.0), (9, 5.0)]
    after = first_of_each_class(specs, 2, skip=1)           # --skip 1 --first 2
    assert [(s.labels[0], s.start[0]) for s in after] == [(1, 3.0), (3, 2.0), (3, 4.0)]


@pytest.mark.parametrize("argv, message", [
    (["--first", "0"], "--first: must be an integer of at least 1; got '0'"),
    (["--skip", "-1"], "--skip: must be an integer of at least 0; got '-1'"),
    (["--first", "two"], "--first: must be an integer of at least 1; got 'two'"),
])
def test_a_count_of_episodes_that_selects_nothing_is_refused(argv, message, capsys):
    with pytest.raises(SystemExit):
        argument_parser().parse_args(argv)
    assert message in capsys.readouterr().err


def test_chain_without_a_sentence_is_refused(tmp_path):
    write_l_floor(tmp_path)
    with pytest.raises(SystemExit, match="eval_semnav: a chain needs its sentence"):
        main(argv=["--map", str(tmp_path / "l_floor.yaml"), "--chain", "1", "3",
                         "--docs", str(tmp_path)])


def test_a_bad_plan_and_a_bad_follower_config_name_their_file(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text('{"not": "a plan"}')
    with pytest.raises(SystemExit, match=r"eval_semnav: plan .*plan.json: not an evaluation"):
        main(argv=["--plan", str(plan), "--docs", str(tmp_path)])
    with pytest.raises(SystemExit, match="eval_semnav: .*missing.yaml"):
        main(argv=["--follower-config", str(tmp_path / "missing.yaml")])
    assert not list(tmp_path.glob("*.md"))


def test_spoken_directions_are_transcribed_with_the_node_s_stt_settings(tmp_path):
    """--stt-config defaults to the file semantic_nav.launch gives the STT node; a bad one
    ends the run naming it before any speech is made."""
    from perception.stt import SttConfig, load_stt_config
    default = argument_parser().parse_args([]).stt_config
    assert default == ROOT / "config" / "semnav_stt.yaml"
    assert load_stt_config(default) == SttConfig(beam_size=5, vocabulary="semnav_phrases.yaml",
                                                 vocabulary_margin=2.0)
    bad = tmp_path / "stt.yaml"
    bad.write_text("beams: 5\n")
    with pytest.raises(EvaluationRunError, match="spoken: .*unknown STT setting 'beams'"):
        spoken_specs([], ["en:175"], bad)
    with pytest.raises(EvaluationRunError, match="spoken: .*nope.yaml not found"):
        spoken_specs([], ["en:175"], tmp_path / "nope.yaml")


def test_unknown_laser_and_class_are_usage_errors(capsys):
    parser = argument_parser()
    for argv in (["--laser", "lms100"], ["--classes", "11"]):
        with pytest.raises(SystemExit) as stop:
            parser.parse_args(argv)
        assert stop.value.code == 2
    assert "invalid choice: 'lms100'" in capsys.readouterr().err
    defaults = parser.parse_args([])
    assert [p.name for p in defaults.maps] == ["office_ring.yaml", "office_comb.yaml"]
    assert EvaluationRun(**vars(defaults)) == EvaluationRun()    # the options are its fields
    assert defaults.docs == workspace() / "docs" / "semantic_nav" / "eval"


def test_a_plan_is_drawn_from_the_phrases_given(tmp_path):
    """--phrases: a new plan's sentences come from that phrase file; a bad one is named."""
    write_l_floor(tmp_path)
    sets = yaml.safe_load(resource("config", "semnav_phrases.yaml").read_text())
    sets["class1"] = {"train": ["roll on to the far wall"], "held_out": ["roll on until the wall"]}
    for split in ("train", "held_out"):
        sets["others"][split].pop(1, None)
    phrases = tmp_path / "phrases.yaml"
    phrases.write_text(yaml.safe_dump(sets))
    argv = ["--map", str(tmp_path / "l_floor.yaml"), "--policy", "expert", "--workers", "1",
            "--episodes-per-class", "1", "--classes", "1", "--laser", "urg04lx",
            "--docs", str(tmp_path),
            "--plan", str(tmp_path / "plan.json"), "--phrases", str(phrases)]
    assert main(argv=argv) == 0
    [spec] = load_plan(tmp_path / "plan.json")
    assert "roll on" in spec.sentence
    del sets["class4"]
    phrases.write_text(yaml.safe_dump(sets))
    (tmp_path / "plan.json").unlink()
    with pytest.raises(SystemExit, match=r"phrases .*phrases.yaml: .*missing .*class4"):
        main(argv=argv)


def test_episodes_the_robot_stayed_in_are_not_reached_at_their_start():
    specs = [EpisodeSpec("f.yaml", (float(k), 0.0, 0.0), (1,), "go on", False) for k in range(3)]
    asked = Reading(False, "I understood: turn around. Shall I go? Please say yes or no.", "no")
    heard = [Heard("en:175", "go on", "go on", ()),
             Heard("en:175", "go on", "go home", (), reading=asked,
                   again=Heard("en:140", "go on", "go home", (), reading=asked)),
             Heard("en:175", "go on", "go on", (), reading=Reading(True))]
    driven = [EpisodeOutcome(specs[0], True, "reached", 9.0, 90, [1]),
              EpisodeOutcome(specs[2], False, "timeout", 60.0, 600, [1])]
    outcomes = with_stayed(specs, heard, driven)
    assert [o.spec for o in outcomes] == specs
    assert outcomes[0] is driven[0] and outcomes[2] is driven[1]
    assert not outcomes[1].success and outcomes[1].path == [[1.0, 0.0, 0.0]]
    assert outcomes[1].reason == ("stayed: answered no to 'I understood: turn around. Shall I "
                                  "go? Please say yes or no.'")

