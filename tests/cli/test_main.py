"""The CLI's failure policy: one line on stderr and exit code 2, never a traceback."""

import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
import typer
from _cli_files import edit_example_and_run

import linkwork
from linkwork.cli import COMMAND_HELP, _real_commands, app, main
from linkwork.errors import LinkworkError, MissingExtraError
from linkwork.models.crank_slider import offset_crank_slider
from linkwork.sweep import check_client, evaluate

ROOT = Path(__file__).resolve().parents[2]


def test_missing_file_one_line_exit_2(tmp_path, capsys):
    rc = main(["analyze", str(tmp_path / "nope.toml")])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and "file not found" in err and "Traceback" not in err


def test_invalid_toml(tmp_path, capsys):
    f = tmp_path / "bad.toml"
    f.write_text("type = 'sine_press\n")
    assert main(["analyze", str(f)]) == 2
    err = capsys.readouterr().err
    assert "invalid TOML" in err and err.count("\n") == 1


#: Every command that reads a mechanism file.
FILE_COMMANDS = [["analyze"], ["balance"], ["reactions"], ["dynamics"], ["report"],
                 ["swashplate", "analyze"]]


@pytest.mark.parametrize("command", FILE_COMMANDS)
@pytest.mark.parametrize("text", ["x = " + "[" * 600 + "]" * 600,
                                  "x = " + "{a=" * 600 + "1" + "}" * 600,
                                  'type = "planar"\nname = ' + "[" * 600 + "]" * 600])
def test_nesting_too_deep_one_line(tmp_path, capsys, text, command):
    """Nested TOML 600 deep (the issue's case; a traceback before): one line, exit 2, no
    output folder, from every command."""
    f = tmp_path / "deep.toml"
    f.write_text(text)
    assert main([*command, str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "deep.toml" in err and "nested too deeply" in err and err.count("\n") == 1, err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", FILE_COMMANDS)
def test_endless_device_one_line(capsys, command, tmp_path):
    if not Path("/dev/zero").exists():
        pytest.skip("no /dev/zero on this system")
    assert main([*command, "/dev/zero", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "/dev/zero" in err and "limit of an input file" in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_a_mechanism_that_does_not_assemble_names_its_file(tmp_path, capsys):
    """An error found while the command works on the file (not by the file's checks) names the
    file too: a coupler of 30 mm for the paper-001 four-bar."""
    err = edit_example_and_run(tmp_path, capsys, "fourbar_paper001.toml", 'length = "300 mm"',
                               'length = "30 mm"')
    assert err.startswith(f"linkwork: error: {tmp_path / 'mech.toml'}: mechanism cannot be "
                          "assembled"), err


def test_an_option_error_is_not_put_on_the_file(tmp_path, capsys):
    rc = main(["analyze", str(Path(__file__).parents[2] / "examples" / "fourbar_paper001.toml"),
               "--angles", "1e300", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("linkwork: error: --angles = "), err


def test_unknown_type(tmp_path, capsys):
    f = tmp_path / "x.toml"
    f.write_text("type = 'perpetual_motion'\n")
    assert main(["analyze", str(f)]) == 2
    assert "unknown type 'perpetual_motion'" in capsys.readouterr().err


def test_usage_errors(capsys):
    assert main(["analyze"]) == 2
    assert main(["--no-such-option"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 2


def test_help_exits_0(capsys):
    assert main(["--help"]) == 0
    assert "analyze" in capsys.readouterr().out


def _edited_example(tmp_path, name, old, new):
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "examples" / name).read_text()
    assert old in text
    p = tmp_path / name
    p.write_text(text.replace(old, new, 1))
    return p


@pytest.mark.parametrize("new,shown", [('omega1 = "1e400 rad/s"', "'1e400 rad/s'"),
                                       ("omega1 = nan", "nan"), ("omega1 = -inf", "-inf")])
def test_non_finite_quantity_in_any_file_is_named_with_file_and_key(new, shown, tmp_path, capsys):
    """The shared unit-aware field types reject inf/nan (also '1e400 rpm', which overflows in
    the unit conversion) with file and key, before any model sees them."""
    p = _edited_example(tmp_path, "fourbar_paper001.toml", 'omega1 = "10 rad/s"', new)
    assert main(["analyze", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"linkwork: error: {p}: driver.omega1: must be a finite number (got {shown})"


def test_union_member_tags_do_not_leak_into_the_key(tmp_path, capsys):
    """pydantic reports errors in a union member at e.g. ('load', 0, 'point', 'str'); the key
    the user sees is the file's key, load.0.point, with the offending value."""
    p = _edited_example(tmp_path, "loom_sixbar.toml", 'point = "R"\nfx', "point = [1, 2, 3]\nfx")
    assert main(["analyze", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert f"{p}: load.0.point: " in err and "(got [1, 2, 3])" in err, err
    assert ".str" not in err and "list[" not in err, err


def test_validator_error_is_keyed_by_its_parameter_and_short(tmp_path, capsys):
    p = _edited_example(tmp_path, "fourbar_paper001.toml", 'mass = "3 kg"', 'mass = "-3 kg"')
    assert main(["analyze", str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"linkwork: error: {p}: body.1.mass (coupler): -3 kg is invalid: "
                   "must be finite and >= 0")


@pytest.mark.parametrize("cmd", ["analyze", "balance", "reactions"])
@pytest.mark.parametrize("name,old,new,expected", [
    ("loom_sixbar.toml", 'body = "ram"', 'body = "frame"',
     "load.0.body: frame is invalid: loads act on moving bodies, not on the frame"),
    ("loom_sixbar.toml", 'point = "R"\nfx', 'point = "Z"\nfx',
     "load.0.point: Z is invalid: no such point of body 'ram'"),
    ("fourbar_paper001.toml", "branches = { B = 1 }", "branches = { Q = 1 }",
     "analysis.branches: Q is invalid: no assembly group has this key; known: ['B']"),
])
def test_planar_file_errors_found_after_validation_carry_file_and_key(
        cmd, name, old, new, expected, tmp_path, capsys):
    """Loads on the frame or on a missing point and unknown branch keys used to be found when
    the analysis ran, and the message lost the file's name."""
    p = _edited_example(tmp_path, name, old, new)
    assert main([cmd, str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"linkwork: error: {p}: {expected}"), err
    assert len(err.splitlines()) == 1


@pytest.mark.parametrize("cmd,name", [(["analyze"], "sine_press.toml"),
                                      (["swashplate", "analyze"], "swashplate_1.toml")])
def test_absurd_speed_stops_with_one_line_instead_of_writing_inf(cmd, name, tmp_path, capsys):
    """speed = 1e200 rad/s overflowed (RuntimeWarnings), wrote inf into the outputs and exited
    0; the files' sanity layer refuses it with one line naming the key and the limit, exit 2
    (behind it, NumPy overflow and infinite result columns also stop with exit 2)."""
    import re
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "examples" / name).read_text()
    p = tmp_path / name
    p.write_text(re.sub(r"(?m)^speed = .*$", "speed = 1e200", text, count=1))
    assert "speed = 1e200" in p.read_text()
    assert main([*cmd, str(p), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert "speed: 1e+200 is invalid: must lie within +-1e+06 rad/s" in err, err


def test_result_with_infinite_column_refuses_to_be_written(tmp_path):
    import numpy as np

    from linkwork.errors import ParameterError
    from linkwork.models.crank_slider import offset_crank_slider
    r = offset_crank_slider(np.linspace(0, 1, 5), 0.05, 4.0, 0.3, omega1=1e200)  # a_C ~ 1e399
    assert np.isinf(r.a_C).all() and np.isfinite(r.V_C).all()
    with pytest.raises(ParameterError, match=r"(eps2|a_C) = inf at 5 of 5 positions .*too large"):
        r.to_csv(tmp_path / "r.csv")
    with pytest.raises(ParameterError, match="= inf at 5 of 5"):
        r.to_json(tmp_path / "r.json")
    nan = offset_crank_slider(np.linspace(0, 6, 7), 0.05, 1.1, 0.3, on_failure="nan")
    assert np.isnan(nan.Y_C).any()
    nan.to_csv(tmp_path / "nan.csv")  # NaN (unassembled positions) is still written


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("command", [
    ["analyze", str(EXAMPLES / "fourbar_paper001.toml")],
    ["balance", str(EXAMPLES / "fourbar_paper001.toml"), "--pareto"],
    ["reactions", str(EXAMPLES / "loom_fourbar_spatial.toml")],
    ["swashplate", "analyze", str(EXAMPLES / "swashplate_1.toml")],
    ["swashplate", "synthesize", "-H", "60 mm", "-R", "100 mm"],
])
def test_unusable_out_folder_is_named_before_the_work(command, tmp_path, capsys, monkeypatch):
    """--out naming an existing file gave '[Errno 17] File exists: ...' without the option, and
    balance/synthesize found it only after their optimisation; now one line naming --out, exit
    2, before any computation (the solvers are made to fail loudly if they are reached)."""
    import linkwork.balancing
    import linkwork.synthesis.swashplate as syn

    def reached(*args, **kwargs):
        raise AssertionError("the work ran before --out was checked")

    monkeypatch.setattr(linkwork.balancing, "compare_balancing", reached)
    monkeypatch.setattr(syn, "synthesize", reached)
    blocker = tmp_path / "results.txt"
    blocker.write_text("not a folder")
    assert main([*command, "--out", str(blocker)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and "a file of that name exists" in err[0]
    assert blocker.read_text() == "not a folder"


def _help_texts() -> list[tuple[list[str], str]]:
    """(command path, help text as it should read) of every option and argument."""
    import typer.main

    from linkwork.cli import app

    out: list[tuple[list[str], str]] = []

    def walk(cmd: typer.main.TyperCommand | typer.main.TyperGroup, path: list[str]) -> None:
        if isinstance(cmd, typer.main.TyperGroup):
            for name, sub in cmd.commands.items():
                walk(sub, [*path, name])
            return
        for p in cmd.params:
            text = getattr(p, "help", None)
            if text:
                out.append((path, text.replace("\\[", "[")))

    walk(typer.main.get_command(app), [])
    return out


def test_every_option_help_prints_as_written(capsys, monkeypatch):
    """'linkwork balance --help' printed '(overrides .angles)': the '[balance]' of the help
    text was taken for Rich markup and dropped. Every option's help must print whole."""
    monkeypatch.setenv("COLUMNS", "200")
    helps = _help_texts()
    assert len(helps) > 30
    for path, text in helps:
        assert main([*path, "--help"]) == 0
        shown = " ".join(capsys.readouterr().out.replace("│", " ").split())
        assert " ".join(text.split()) in shown, (path, text)


@pytest.mark.parametrize("example,old,new,words,cmd", [
    # pint reads the radian as dimensionless: "2 Hz" passed as 2 rad/s (an engineer means
    # 2 rev/s = 12.57 rad/s), "600 rpm" as a productivity of 62.8 /s (meant: 10 /s)
    ("sine_press.toml", 'speed = "120 rpm"', 'speed = "2 Hz"', ["crank.speed", "2 Hz", "rpm"],
     ("analyze",)),
    ("swashplate_1.toml", 'speed = "50 rpm"', 'speed = "0.8 Hz"', ["operation.speed", "Hz"],
     ("swashplate", "analyze")),
    ("swashplate_4a.toml", 'productivity = "600 1/min"', 'productivity = "600 rpm"',
     ["operation.productivity", "angle unit", "1/min"], ("swashplate", "analyze")),
])
def test_cli_angle_unit_traps_are_refused(example, old, new, words, cmd, tmp_path, capsys):
    err = edit_example_and_run(tmp_path, capsys, example, old, new, cmd=cmd)
    for w in words:
        assert w in err, (w, err)


# --- the command itself: --version, -h, python -m linkwork ---------------------------------

def test_version_prints_the_package_version(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out == f"linkwork {linkwork.__version__}\n"


@pytest.mark.parametrize("cmd", [[], ["analyze"], ["balance"], ["reactions"], ["swashplate"],
                                 ["swashplate", "analyze"], ["swashplate", "synthesize"]])
def test_short_help_is_long_help_on_every_command(cmd, capsys):
    assert main([*cmd, "--help"]) == 0
    long = capsys.readouterr().out
    assert main([*cmd, "-h"]) == 0
    assert capsys.readouterr().out == long and "Usage: linkwork" in long


def test_python_dash_m_linkwork_runs_the_cli():
    root = Path(__file__).resolve().parents[2]
    r = subprocess.run([sys.executable, "-m", "linkwork", "--version"], cwd=root,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stdout.startswith("linkwork ")
    r = subprocess.run([sys.executable, "-m", "linkwork", "analyze", "no-such-file.toml"],
                       cwd=root, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1


# --- missing optional extras: one line naming the install command --------------------------

def test_scheduler_without_dask_is_one_line_before_any_output(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # as if the extra were missing
    out = tmp_path / "o"
    example = Path(__file__).resolve().parents[2] / "examples" / "loom_fourbar_spatial.toml"
    for cmd in (["reactions", str(example), "--tolerance-study", "10", "--scheduler",
                 "tcp://127.0.0.1:8786"],
                ["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", "--delta", "10 deg",
                 "--scheduler", "tcp://127.0.0.1:8786"]):
        assert main([*cmd, "--out", str(out)]) == 2
        assert capsys.readouterr().err == ("linkwork: error: --scheduler needs dask: "
                                           "pip install 'linkwork[dask]'\n")
        assert not out.exists()


@pytest.mark.parametrize("address", ["foo bar", "tcp://host:notaport", "http://host:1",
                                     "tcp://host:99999", "::::", ""])
def test_malformed_scheduler_address_is_one_line(address, tmp_path, capsys):
    cmd = ["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", "--delta", "10 deg",
           "--scheduler", address, "--out", str(tmp_path / "o")]
    assert main(cmd) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler" in err and "tcp://10.0.0.1:8786" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("address", ["tcp://10.0.0.1:8786", "10.0.0.1:8786", "localhost",
                                     "tls://[::1]:8786", "scheduler-0.cluster.local:8786"])
def test_well_formed_addresses_pass_the_check(address):
    check_client(address, option="--scheduler")  # dask is installed with the test extras


def test_evaluate_with_an_address_but_no_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(MissingExtraError, match=r"client needs dask: pip install "
                                                r"'linkwork\[dask\]'") as info:
        evaluate(np.sqrt, np.arange(4.0), client="tcp://127.0.0.1:8786")
    assert isinstance(info.value, ImportError) and isinstance(info.value, LinkworkError)


def test_to_frame_without_pandas_names_pip_install_pandas(monkeypatch):
    res = offset_crank_slider(np.radians([0.0, 90.0]), L1=0.05, lambda2=4.0, lambda_e=0.0,
                              omega1=10.0, eps1=0.0)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas") as info:
        res.to_frame()
    assert isinstance(info.value, LinkworkError)
    assert "linkwork[pandas]" in str(info.value)


def test_pyproject_names_the_extras_the_messages_name():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text()
                           )["project"]["optional-dependencies"]
    assert any(r.startswith("dask[distributed]") for r in extras["dask"])
    assert any(r.startswith("pandas") for r in extras["pandas"])


def _commands(group, path=()):
    for name, cmd in group.commands.items():
        if hasattr(cmd, "commands"):
            yield from _commands(cmd, (*path, name))
        else:
            yield (*path, name), cmd


def test_one_default_output_folder_for_every_command_and_git_ignores_it():
    defaults = {" ".join(path): next(p.default for p in cmd.params if p.name == "out")
                for path, cmd in _commands(typer.main.get_command(app))
                if any(p.name == "out" for p in cmd.params)}
    assert set(defaults) >= {"analyze", "balance", "reactions", "swashplate analyze",
                             "swashplate synthesize"}
    assert {str(v) for v in defaults.values()} == {"linkwork-output"}
    ignored = (ROOT / ".gitignore").read_text().splitlines()
    assert "linkwork-output/" in ignored and "demo-output/" in ignored


# --- start-up: `linkwork --help` lists the commands without importing their modules ---------

_HELP_SCRIPT = """
import sys
from linkwork.cli import _real_commands, main
main(["--help"]); main(["--version"])
heavy = sorted(m for m in ("linkwork.studies", "linkwork.io", "linkwork.planar", "pydantic",
                           "scipy", "matplotlib", "pint") if m in sys.modules)
print("HEAVY", heavy)
_real_commands()
main(["--help"])
"""


def test_help_and_version_import_no_study_and_list_the_commands_as_their_modules_do():
    r = subprocess.run([sys.executable, "-c", _HELP_SCRIPT], cwd=ROOT, capture_output=True,
                       text=True, timeout=120, env={"COLUMNS": "100", "PATH": ""})
    assert r.returncode == 0, r.stderr
    lazy, rest = r.stdout.split("HEAVY ")
    heavy, loaded = rest.split("\n", 1)
    assert heavy == "[]"
    version = f"linkwork {linkwork.__version__}\n"
    assert lazy.endswith(version) and lazy[:-len(version)] == loaded  # same listing


_ONE_COMMAND_SCRIPT = """
import sys
from linkwork.cli import main
code = main(["analyze", "no-such-file.toml"])
print("CODE", code, sorted(m for m in sys.modules if m.startswith("linkwork.cli.")
                          and m.split(".")[2] in {"balance", "reactions", "report",
                                                  "synthesize"}))
"""


def test_a_command_imports_only_its_own_module():
    """``linkwork analyze`` (here failing on a missing file: an error path) imports the analyze
    module, not the other commands' (their studies, the report, the synthesis; the swashplate
    module renders analyze's swash-plate files, so analyze imports it)."""
    r = subprocess.run([sys.executable, "-c", _ONE_COMMAND_SCRIPT], cwd=ROOT,
                       capture_output=True, text=True, timeout=120, env={"PATH": ""})
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip().splitlines()[-1] == "CODE 2 []"
    assert "no-such-file.toml" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_command_help_is_the_first_paragraph_of_each_commands_help():
    real = _real_commands()
    assert list(real) == list(COMMAND_HELP)
    for name, cmd in real.items():
        assert " ".join(cmd.help.split("\n\n")[0].split()) == COMMAND_HELP[name]


def test_command_modules_are_still_importable_from_linkwork_cli():
    from linkwork.cli import (
        COMMAND_MODULES,
        analyze,
        balance,
        dynamics,
        examples,
        reactions,
        report,
        swashplate,
        synthesize,
    )
    assert COMMAND_MODULES == (analyze, balance, dynamics, reactions, report, swashplate,
                               synthesize, examples)


def _complete(words: str, cword: int) -> list[str]:
    env = {"PATH": "", "_LINKWORK_COMPLETE": "complete_bash", "COMP_WORDS": words,
           "COMP_CWORD": str(cword)}
    r = subprocess.run([sys.executable, "-c", "from linkwork.cli import main; main()"],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return r.stdout.split()


def test_shell_completion_of_commands_sub_commands_and_options():
    assert _complete("linkwork ana", 1) == ["analyze"]
    assert _complete("linkwork swashplate ", 2) == ["analyze", "synthesize"]
    assert _complete("linkwork reactions --met", 2) == ["--method"]


def test_show_completion_prints_the_bash_script(capsys, monkeypatch):
    """Typer detects the shell from the process tree (shellingham), which differs between a
    terminal, make and CI (where it found 'sh'): the detection is pinned to bash here."""
    import typer.completion

    monkeypatch.setattr(typer.completion, "_get_shell_name", lambda: "bash")
    assert main(["--show-completion"]) == 0
    assert "_LINKWORK_COMPLETE=complete_bash" in capsys.readouterr().out


def test_the_command_line_fixes_its_heap(monkeypatch):
    """``linkwork`` owns its process: every command starts with roomy_process_heap."""
    import linkwork.cli as cli

    calls = []
    monkeypatch.setattr(cli, "roomy_process_heap", lambda: calls.append(1) or True)
    assert cli.main(["examples"]) == 0
    assert calls == [1]
