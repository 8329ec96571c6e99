"""Scene files: parsing into typed objects, defaults, round trip, and every validation error.

The expected keys, defaults and ranges are the scene contract of issue 5.  Each
error test writes a small file and checks that the message names the file, the
dotted key and the value (the CLI prints it as one line and exits 2).
"""

import dataclasses
import json
import os
import re
from pathlib import Path

import pytest

from lcchain.core.errors import ParameterError
from lcchain.scenes.load import load_scene, parse_scene
from lcchain.scenes.schema import (
    DEFAULT_TITLE,
    Analysis,
    ChainSpec,
    Effects,
    ExcitationSpec,
    Losses,
    Output,
    PreferredValues,
    Scene,
    Tolerance,
    Units,
    Walls,
)

SCENES = Path(__file__).resolve().parent.parent / "examples" / "scenes"
EXAMPLES = sorted(SCENES.glob("*.toml"))

MINIMAL = '[chain]\ncase = "two-mass"\nN = 50\n'


def _write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _error(tmp_path, text):
    path = _write(tmp_path, text)
    with pytest.raises(ParameterError) as info:
        load_scene(path)
    return str(path), info.value


def _assert_names(message, path, key, value_text):
    assert message.startswith(f"{path}: "), message
    assert f" {key} = {value_text} is not allowed: expected " in message, message


# ------------------------------------------------------------------ examples


def test_the_required_examples_exist():
    names = {p.name for p in EXAMPLES}
    assert {
        "cradle.toml",
        "bench.toml",
        "uniform-vs-optimal-uniform.toml",
        "uniform-vs-optimal-optimal.toml",
        "spacetime.toml",
        "walls.toml",
    } <= names


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_every_example_parses_and_has_a_comment_header(path):
    scene = load_scene(path)
    assert scene.source == str(path)
    assert path.read_text(encoding="utf-8").startswith("#")


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_to_dict_round_trips_through_json(path):
    scene = load_scene(path)
    data = json.loads(json.dumps(scene.to_dict()))
    assert parse_scene(data) == scene
    assert parse_scene(scene.to_dict()) == scene


def test_cradle_is_the_papers_cradle():
    scene = load_scene(SCENES / "cradle.toml")
    assert scene.chain == ChainSpec("two-mass", 100)
    assert scene.excitation.kind == "kick"
    assert scene.analysis.transits == 3
    assert scene.analysis.accuracy == 1e-3 and scene.analysis.dt is None
    assert scene.effects == Effects()


def test_bench_scene():
    scene = load_scene(SCENES / "bench.toml")
    assert scene.title == "Bench cradle, 50 cells"
    assert scene.chain == ChainSpec("two-mass", 50)
    assert scene.units == Units(10e-6, 10e-9)
    assert scene.excitation == ExcitationSpec("pulse", 1e-3, "gaussian", 0.2)
    assert scene.effects == Effects(
        losses=Losses(100.0),
        tolerance=Tolerance(L=0.05, C=0.05, samples=20, seed=7),
        preferred_values=PreferredValues("E24"),
    )
    assert scene.output.plots == ("overlay", "histogram")
    assert scene.output.report == "out/bench.json"


def test_the_uniform_vs_optimal_pair_differs_only_in_the_chain_case():
    uniform = load_scene(SCENES / "uniform-vs-optimal-uniform.toml").to_dict()
    optimal = load_scene(SCENES / "uniform-vs-optimal-optimal.toml").to_dict()
    assert uniform["chain"] == {"case": "uniform-free", "N": 50}
    assert optimal["chain"] == {"case": "two-mass", "N": 50}
    for table in ("units", "excitation", "effects", "analysis"):
        assert uniform[table] == optimal[table]


def test_spacetime_and_walls_scenes():
    spacetime = load_scene(SCENES / "spacetime.toml")
    assert spacetime.chain == ChainSpec("two-mass", 40)
    assert spacetime.output.probes == "all"
    assert spacetime.output.plots == ("spacetime", "overlay")
    assert spacetime.analysis.transits == 4
    walls = load_scene(SCENES / "walls.toml")
    assert walls.effects.walls == Walls(0.01)
    assert walls.excitation.shape == "rect"


# ------------------------------------------------------------------ defaults


def test_defaults_of_a_minimal_scene(tmp_path):
    scene = load_scene(_write(tmp_path, MINIMAL))
    assert scene.title == DEFAULT_TITLE == "lcchain scene"
    assert scene.chain == ChainSpec("two-mass", 50, None, None)
    assert scene.units == Units(L0=10e-6, C0=10e-9)
    assert scene.excitation == ExcitationSpec(kind="kick", I0=1e-3, shape=None, width=None)
    assert scene.effects == Effects() == Effects({"losses": None}) == Effects(walls=None)
    assert scene.analysis == Analysis(transits=1, accuracy=1e-3, dt=None, backend="batch", method="trap")
    assert scene.output == Output(probes="ends", report=None, plots=("overlay",))
    assert scene.to_dict()["effects"] == {}


def test_defaults_inside_effect_tables(tmp_path):
    scene = load_scene(_write(tmp_path, MINIMAL + "[effects.tolerance]\n"))
    assert scene.effects.tolerance == Tolerance(L=0.0, C=0.0, samples=1, seed=0)


def test_dt_replaces_the_default_accuracy(tmp_path):
    scene = load_scene(_write(tmp_path, MINIMAL + "[analysis]\ndt = 0.05\nmethod = \"gear\"\n"))
    assert scene.analysis.dt == 0.05 and scene.analysis.accuracy is None
    assert scene.analysis.method == "gear"
    assert "accuracy" not in scene.to_dict()["analysis"]
    assert Analysis(dt=0.05).accuracy is None
    assert Analysis().accuracy == 1e-3


def test_integers_are_accepted_where_floats_are_expected(tmp_path):
    scene = load_scene(_write(tmp_path, MINIMAL + "[units]\nL0 = 1\nC0 = 2\n[effects.losses]\nQ = 100\n"))
    assert scene.units == Units(1.0, 2.0)
    assert type(scene.units.L0) is float and type(scene.effects.losses.Q) is float


def test_custom_chain_n_is_optional_and_values_are_tuples(tmp_path):
    text = '[chain]\ncase = "custom"\nmasses = [2, 1, 1, 2]\nsprings = [0, 0.5, 1, 0.5, 0]\n'
    scene = load_scene(_write(tmp_path, text))
    assert scene.chain == ChainSpec("custom", 4, (2.0, 1.0, 1.0, 2.0), (0.0, 0.5, 1.0, 0.5, 0.0))
    assert isinstance(scene.chain.masses, tuple)
    assert load_scene(_write(tmp_path, text.replace("masses", "N = 4\nmasses"))) == scene
    assert parse_scene(scene.to_dict()) == scene


def test_objects_are_immutable_and_hashable(tmp_path):
    scene = load_scene(SCENES / "bench.toml")
    with pytest.raises(dataclasses.FrozenInstanceError):
        scene.title = "x"  # type: ignore[misc]
    assert hash(scene) == hash(load_scene(SCENES / "bench.toml"))


def test_parse_scene_without_a_source_names_no_file():
    with pytest.raises(ParameterError, match=r"^chain\.N = 2 is not allowed"):
        parse_scene({"chain": {"case": "two-mass", "N": 2}})


def test_parse_scene_names_the_source_it_is_given():
    with pytest.raises(ParameterError, match=r"^scene\.json: chain\.N = 2 is not allowed"):
        parse_scene({"chain": {"case": "two-mass", "N": 2}}, source="scene.json")


# ----------------------------------------------------------- validation errors

# (TOML text, dotted key, the value as the message shows it, a fragment of what is allowed)
BAD = {
    # issue 5's list
    "unknown top-level key": ("colour = 'red'\n" + MINIMAL, "colour", "'red'", "one of the keys title, chain"),
    "unknown chain key": (MINIMAL + "mass = 3\n", "chain.mass", "3", "case, N, masses, springs in [chain]"),
    "unknown effect": (MINIMAL + "[effects.friction]\nmu = 1\n", "effects.friction", "{'mu': 1}", "losses, walls, coupling, tolerance, preferred_values, coil_capacitance, coil_resistance, capacitor_esr, capacitor_esl"),
    "unknown key in an effect": (MINIMAL + "[effects.tolerance]\nR = 0.1\n", "effects.tolerance.R", "0.1", "L, C, samples, seed"),
    "N a string": ('[chain]\ncase = "two-mass"\nN = "50"\n', "chain.N", "'50'", "an integer from 3 to 100000"),
    "N a float": ('[chain]\ncase = "two-mass"\nN = 50.0\n', "chain.N", "50.0", "an integer"),
    "N a boolean": ('[chain]\ncase = "two-mass"\nN = true\n', "chain.N", "True", "an integer"),
    "dt a string": (MINIMAL + '[analysis]\ndt = "0.05"\n', "analysis.dt", "'0.05'", "a number, 0 < dt <= 1"),
    "plots a string": (MINIMAL + '[output]\nplots = "overlay"\n', "output.plots", "'overlay'", "a list of distinct names"),
    "L0 a boolean": (MINIMAL + "[units]\nL0 = true\n", "units.L0", "True", "a finite number > 0"),
    "N = 2": ('[chain]\ncase = "two-mass"\nN = 2\n', "chain.N", "2", "an integer from 3 to 100000"),
    "N too large": ('[chain]\ncase = "two-mass"\nN = 100001\n', "chain.N", "100001", "an integer from 3 to 100000"),
    "perfect N = 20001": ('[chain]\ncase = "perfect"\nN = 20001\n', "chain.N", "20001", "3 to 20000"),
    "negative tolerance": (MINIMAL + "[effects.tolerance]\nL = -0.05\n", "effects.tolerance.L", "-0.05", "0 <= L < 1"),
    "tolerance of 100 %": (MINIMAL + "[effects.tolerance]\nC = 1.0\n", "effects.tolerance.C", "1.0", "0 <= C < 1"),
    "width = 0": (MINIMAL + '[excitation]\nkind = "pulse"\nshape = "rect"\nwidth = 0\n', "excitation.width", "0", "0.001 <= width <= 1000"),
    "width < 0": (MINIMAL + '[excitation]\nkind = "pulse"\nshape = "rect"\nwidth = -0.2\n', "excitation.width", "-0.2", "0.001 <= width <= 1000"),
    "unknown E-series": (MINIMAL + '[effects.preferred_values]\nseries = "E6"\n', "effects.preferred_values.series", "'E6'", "E12 | E24 | E96"),
    "title with a newline": ('title = "one\\n.control"\n' + MINIMAL, "title", repr("one\n.control"), "a newline"),
    "title starting with .control": ('title = ".control"\n' + MINIMAL, "title", "'.control'", "dot-command"),
    # the rest of the contract
    "unknown case": ('[chain]\ncase = "three-mass"\nN = 50\n', "chain.case", "'three-mass'", "one-mass | two-mass"),
    "missing case": ("[chain]\nN = 50\n", "chain.case", "None", "one-mass | two-mass"),
    "missing chain": ("title = 'x'\n", "chain", "None", "(required)"),
    "chain not a table": ("chain = 3\n", "chain", "3", "a table [chain]"),
    "missing N": ('[chain]\ncase = "two-mass"\n', "chain.N", "None", "(required)"),
    "pulse without shape": (MINIMAL + '[excitation]\nkind = "pulse"\nwidth = 0.2\n', "excitation.shape", "None", 'gaussian | rect (required when kind = "pulse")'),
    "pulse without width": (MINIMAL + '[excitation]\nkind = "pulse"\nshape = "gaussian"\n', "excitation.width", "None", "required when kind"),
    "shape without pulse": (MINIMAL + '[excitation]\nshape = "gaussian"\n', "excitation.shape", "'gaussian'", 'no shape unless kind = "pulse"'),
    "width without pulse": (MINIMAL + '[excitation]\nkind = "kick"\nwidth = 0.2\n', "excitation.width", "0.2", 'no width unless kind = "pulse"'),
    "unknown excitation": (MINIMAL + '[excitation]\nkind = "step"\n', "excitation.kind", "'step'", "kick | displacement | pulse"),
    "I0 = 0": (MINIMAL + "[excitation]\nI0 = 0\n", "excitation.I0", "0", "1e-100 <= I0 <= 1e+100"),
    "custom without masses": ('[chain]\ncase = "custom"\nN = 3\nsprings = [0, 1, 1, 0]\n', "chain.masses", "None", 'required for case = "custom"'),
    "custom without springs": ('[chain]\ncase = "custom"\nmasses = [1, 1, 1]\n', "chain.springs", "None", 'required for case = "custom"'),
    "masses with a named case": (MINIMAL + "masses = [1, 1, 1]\n", "chain.masses", "[1, 1, 1]", 'no masses unless case = "custom"'),
    "springs with a named case": (MINIMAL + "springs = [0, 1, 1, 0]\n", "chain.springs", "[0, 1, 1, 0]", 'no springs unless case = "custom"'),
    "springs wrong length": ('[chain]\ncase = "custom"\nmasses = [1, 1, 1]\nsprings = [0, 1, 0]\n', "chain.springs", "[0, 1, 0]", "N+1 = 4 numbers"),
    "N disagrees with masses": ('[chain]\ncase = "custom"\nN = 4\nmasses = [1, 1, 1]\nsprings = [0, 1, 1, 0]\n', "chain.N", "4", "len(chain.masses) = 3"),
    "a negative mass": ('[chain]\ncase = "custom"\nmasses = [1, -1, 1]\nsprings = [0, 1, 1, 0]\n', "chain.masses[1]", "-1", "a finite number > 0"),
    "an inner spring of 0": ('[chain]\ncase = "custom"\nmasses = [1, 1, 1]\nsprings = [0, 0, 1, 0]\n', "chain.springs[1]", "0", "(an inner spring)"),
    "an infinite mass": ('[chain]\ncase = "custom"\nmasses = [1, inf, 1]\nsprings = [0, 1, 1, 0]\n', "chain.masses[1]", "inf", "a finite number"),
    "a mass as text": ('[chain]\ncase = "custom"\nmasses = [1, "1", 1]\nsprings = [0, 1, 1, 0]\n', "chain.masses[1]", "'1'", "a number"),
    "too few masses": ('[chain]\ncase = "custom"\nmasses = [1, 1]\nsprings = [0, 1, 0]\n', "chain.masses", "[1, 1]", "a list of 3 to 100000"),
    "accuracy and dt": (MINIMAL + "[analysis]\naccuracy = 1e-3\ndt = 0.05\n", "analysis.dt", "0.05", "mutually exclusive"),
    "accuracy = 1": (MINIMAL + "[analysis]\naccuracy = 1\n", "analysis.accuracy", "1", "0 < accuracy < 1"),
    "dt > 1": (MINIMAL + "[analysis]\ndt = 2\n", "analysis.dt", "2", "0 < dt <= 1"),
    "transits = 0": (MINIMAL + "[analysis]\ntransits = 0\n", "analysis.transits", "0", "an integer from 1 to 1000"),
    "unknown backend": (MINIMAL + '[analysis]\nbackend = "xspice"\n', "analysis.backend", "'xspice'", "batch | shared"),
    "unknown method": (MINIMAL + '[analysis]\nmethod = "euler"\n', "analysis.method", "'euler'", "trap | gear"),
    "Q missing": (MINIMAL + "[effects.losses]\n", "effects.losses.Q", "None", "1 <= Q <= 1e+10"),
    "Q negative": (MINIMAL + "[effects.losses]\nQ = -1\n", "effects.losses.Q", "-1", "1 <= Q <= 1e+10"),
    "Q not a number": (MINIMAL + "[effects.losses]\nQ = nan\n", "effects.losses.Q", "nan", "1 <= Q <= 1e+10"),
    "K0 = 0": (MINIMAL + "[effects.walls]\nK0 = 0\n", "effects.walls.K0", "0", "0 < K0 <= 1e+12"),
    "samples = 0": (MINIMAL + "[effects.tolerance]\nsamples = 0\n", "effects.tolerance.samples", "0", "an integer from 1 to 10000"),
    "negative seed": (MINIMAL + "[effects.tolerance]\nseed = -1\n", "effects.tolerance.seed", "-1", "an integer >= 0"),
    "unknown probes": (MINIMAL + '[output]\nprobes = "middle"\n', "output.probes", "'middle'", "ends | all"),
    "unknown plot": (MINIMAL + '[output]\nplots = ["overlay", "bode"]\n', "output.plots[1]", "'bode'", "overlay | spacetime | histogram"),
    "repeated plot": (MINIMAL + '[output]\nplots = ["overlay", "overlay"]\n', "output.plots", "['overlay', 'overlay']", "distinct"),
    "report not a string": (MINIMAL + "[output]\nreport = 3\n", "output.report", "3", "a file path"),
    "spacetime without probes = all": (MINIMAL + '[output]\nplots = ["spacetime"]\n', "output.plots", "['spacetime']", 'unless output.probes = "all"'),
    "histogram without tolerance": (MINIMAL + '[output]\nplots = ["histogram"]\n', "output.plots", "['histogram']", "unless effects.tolerance.samples > 1"),
    "histogram with one sample": (
        MINIMAL + '[effects.tolerance]\nL = 0.05\nsamples = 1\n[output]\nplots = ["histogram"]\n',
        "output.plots", "['histogram']", "unless effects.tolerance.samples > 1",
    ),
}


@pytest.mark.parametrize("case", list(BAD), ids=list(BAD))
def test_validation_error_names_file_key_value_and_range(tmp_path, case):
    text, key, value_text, allowed = BAD[case]
    path, error = _error(tmp_path, text)
    message = str(error)
    _assert_names(message, path, key, value_text)
    assert allowed in message.split("expected ", 1)[1], message
    assert error.field == key and error.where == path
    assert "\n" not in message  # one line for the command line


def test_toml_syntax_error_reports_the_line(tmp_path):
    path, error = _error(tmp_path, MINIMAL + "[units]\nL0 = = 1e-5\n")
    message = str(error)
    assert message.startswith(f"{path}: line 5 = 'L0 = = 1e-5' is not allowed: expected valid TOML (")
    assert re.search(r"\(at line 5, column \d+\)\)$", message), message


def test_duplicate_key_is_a_toml_error(tmp_path):
    path, error = _error(tmp_path, MINIMAL + "N = 60\n")
    assert str(error).startswith(f"{path}: line 4 = 'N = 60' is not allowed: expected valid TOML")


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.toml"
    with pytest.raises(ParameterError) as info:
        load_scene(path)
    message = str(info.value)
    assert message.startswith(f"{path}: scene = {str(path)!r} is not allowed: expected a readable file (")
    assert "No such file" in message


@pytest.mark.parametrize("kind, said", [("fifo", "a FIFO"), ("folder", "a folder"), ("link to a fifo", "a FIFO")])
def test_only_a_regular_file_is_read(tmp_path, kind, said):
    """A FIFO would block the read and a device never end: refused before a byte is read."""
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "folder.toml").mkdir()
    os.symlink(tmp_path / "fifo", tmp_path / "link.toml")
    path = {"fifo": tmp_path / "fifo", "folder": tmp_path / "folder.toml", "link to a fifo": tmp_path / "link.toml"}
    with pytest.raises(ParameterError, match=f"expected a regular file \\(this is {said}\\)"):
        load_scene(path[kind])


def test_a_scene_nested_too_deeply_is_a_clear_error(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text(MINIMAL + "x = " + "[" * 100_000 + "\n")
    with pytest.raises(ParameterError, match="nests too deeply") as info:
        load_scene(path)
    assert info.value.where == str(path)


@pytest.mark.parametrize("path", [42, None, b"s.toml", 1.5])
def test_load_scene_wants_a_file_name(path):
    with pytest.raises(ParameterError, match="^path = "):
        load_scene(path)


def test_not_utf8(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(MINIMAL.encode() + b"title = '\xe9'\n")
    with pytest.raises(ParameterError, match=r"expected UTF-8 text"):
        load_scene(path)


# -------------------------------------------------- the objects check themselves


def test_objects_built_in_python_are_checked_too():
    with pytest.raises(ParameterError, match=r"^effects\.tolerance\.L = -0\.1 is not allowed"):
        Tolerance(L=-0.1)
    with pytest.raises(ParameterError, match=r"^analysis\.dt = 0\.05 is not allowed: expected no dt when"):
        Analysis(accuracy=1e-3, dt=0.05)
    with pytest.raises(ParameterError, match=r"^output\.plots = \['spacetime'\] is not allowed"):
        Scene("t", ChainSpec("two-mass", 50), Units(), ExcitationSpec(), Effects(), Analysis(), Output(plots=("spacetime",)))
    with pytest.raises(ParameterError, match=r"^title = "):
        Scene(".tran 1 2", ChainSpec("two-mass", 50), Units(), ExcitationSpec(), Effects(), Analysis(), Output())
    with pytest.raises(ParameterError, match=r"^effects\.walls = "):
        Effects(walls=0.01)  # type: ignore[arg-type]


def test_source_is_not_part_of_equality_or_to_dict(tmp_path):
    scene = load_scene(SCENES / "cradle.toml")
    assert "source" not in scene.to_dict()
    assert dataclasses.replace(scene, source=None) == scene


# ------------------------------------------------------ effects from the registry (issue 30)
#: One value of each registered effect's fields (a new effect in the registry needs a line here, or fails).
_EFFECT_TABLES = {"losses": {"Q": 100.0}, "walls": {"K0": 0.5}, "coupling": {"k": 0.1},
                  "tolerance": {"L": 0.01, "C": 0.02, "samples": 3, "seed": 4}, "preferred_values": {"series": "E24"},
                  "coil_capacitance": {"ratio": 0.01}, "coil_resistance": {"R": 0.002}, "capacitor_esr": {"R": 0.003},
                  "capacitor_esl": {"L": 0.004}}


def test_every_registered_effect_is_a_scene_table_that_round_trips(tmp_path):
    from lcchain.circuit.effects import EFFECTS
    from lcchain.scenes.plan import scene_request

    assert set(_EFFECT_TABLES) == set(EFFECTS)
    text = MINIMAL + "".join(f"[effects.{key}]\n" + "".join(f"{name} = {json.dumps(value)}\n"
                                                              for name, value in table.items())
                             for key, table in _EFFECT_TABLES.items())
    scene = load_scene(_write(tmp_path, text))
    assert scene.to_dict()["effects"] == _EFFECT_TABLES
    assert parse_scene(scene.to_dict()) == scene
    assert {type(e) for e in scene.effects.present()} == set(EFFECTS.values())
    assert scene_request(scene).effects == scene.effects.present()  # nothing parsed and then dropped


@pytest.mark.parametrize("key, field", [("coil_capacitance", "ratio"), ("coil_resistance", "R"),
                                        ("capacitor_esr", "R"), ("capacitor_esl", "L")])
@pytest.mark.parametrize("value, shown", [("-1", "-1"), ("2e6", "2000000.0")])  # TOML's int, and float
def test_a_real_part_out_of_range_names_its_key(tmp_path, key, field, value, shown):
    path, error = _error(tmp_path, MINIMAL + f"[effects.{key}]\n{field} = {value}\n")
    unit = {'ratio': 'capacitance / C0', 'R': 'resistance / sqrt(L0/C0)', 'L': 'inductance / L0'}[field]
    assert str(error) == (f"{path}: effects.{key}.{field} = {shown} is not allowed: expected a number, "
                          f"0 < {field} <= 1e+06 ({unit}; a parasitic larger than 1e+06 times its bulk part is "
                          "another part)")


def test_effects_hold_only_registered_effects():
    from lcchain.circuit.effects import CoilCapacitance

    with pytest.raises(ParameterError, match=r"^effects\.friction = "):
        Effects(friction=None)
    with pytest.raises(ParameterError, match=r"^effects\.coil_capacitance = "):
        Effects(coil_capacitance=Losses(10.0))
    effects = Effects(coil_capacitance=CoilCapacitance(0.1))
    assert effects.coil_capacitance == CoilCapacitance(0.1) and effects.losses is None
    assert effects.get(CoilCapacitance) == CoilCapacitance(0.1)
    with pytest.raises(AttributeError):
        effects.friction  # noqa: B018
