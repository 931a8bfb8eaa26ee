"""User strings never run through Rich's highlighter or markup (issue 19, part 7): a mechanism
name of 100 kB took 94 s (the highlighter is quadratic in a string's length); a name with
brackets or emoji codes prints as written."""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest
from rich.highlighter import ReprHighlighter

import linkwork.plot
from linkwork.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LONG = "x" * 100_000


def _renamed(example: str, name: str, folder: Path) -> Path:
    """``example`` with its (first) ``name`` replaced by ``name``."""
    text = (EXAMPLES / example).read_text(encoding="utf-8")
    text = re.sub(r'^name = ".*"', lambda _: f'name = "{name}"', text, count=1, flags=re.M)
    path = folder / example
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def no_highlighter(monkeypatch):
    """Rich's highlighter fails if called; the figures are closed unsaved (a figure titled with
    a 100 kB name takes minutes to draw: not what this test is about)."""
    def fail(self, text):
        raise AssertionError(f"highlighter called on {str(text)[:60]!r}")

    def close(fig, path, dpi=120):
        linkwork.plot.pyplot().close(fig)
        return Path(path)

    monkeypatch.setattr(ReprHighlighter, "highlight", fail)
    monkeypatch.setattr(linkwork.plot, "save", close)


@pytest.mark.parametrize(("example", "command"), [
    ("fourbar_paper001.toml", ["analyze"]),
    ("fourbar_paper001.toml", ["reactions", "--no-plots"]),
    ("fourbar_paper001.toml", ["balance"]),
    ("sine_press.toml", ["analyze"]),
    ("swashplate_4a.toml", ["analyze"]),
])
def test_a_100_kB_name_is_printed_whole_without_the_highlighter(example, command, tmp_path,
                                                                capsys, no_highlighter):
    path = _renamed(example, LONG, tmp_path)
    start = time.perf_counter()
    assert main([command[0], str(path), *command[1:], "--out", str(tmp_path / "out")]) == 0
    assert time.perf_counter() - start < 30.0  # the highlighter alone took 94 s
    out = capsys.readouterr().out
    if command[0] == "analyze":  # the name heads the output, folded over many lines
        assert LONG in re.sub(r"[\s│┃]", "", out)


def test_names_print_as_written_not_as_markup_or_emoji(tmp_path, capsys, no_highlighter):
    """A name with Rich markup ("[bold]") or an emoji code (":smile:") prints as written."""
    name = "press [bold]B[/bold] :smile: [deg]"
    path = _renamed("fourbar_paper001.toml", name, tmp_path)
    assert main(["analyze", str(path), "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{name}: mobility W = 1")
    out_dir = tmp_path / "[red]out[/red]"
    assert main(["reactions", str(path), "--no-plots", "--out", str(out_dir)]) == 0
    assert f"{out_dir}/reactions.csv" in capsys.readouterr().out.replace("\n", "")


def test_steps_bar_only_on_a_terminal_and_named_by_its_step():
    import io

    from rich.console import Console

    from linkwork.cli._console import steps
    pipe = Console(file=io.StringIO(), force_terminal=False)
    with steps(2, console=pipe) as step:
        step("writing a.csv")
        step("writing b.json")
    assert pipe.file.getvalue() == ""  # a pipe or a file gets nothing
    term = Console(file=io.StringIO(), force_terminal=True, width=100)
    with steps(2, console=term) as step:
        step("writing a.csv")
        step("writing [b].json")  # markup in a name is shown as written
    shown = term.file.getvalue()
    assert "writing a.csv" in shown and "writing [b].json" in shown


def test_counting_bar_only_on_a_terminal_and_counts():
    import io

    from rich.console import Console

    from linkwork.cli._console import counting
    pipe = Console(file=io.StringIO(), force_terminal=False)
    with counting("solving [x]", console=pipe) as progress:
        progress(5, 10)
    assert pipe.file.getvalue() == ""
    term = Console(file=io.StringIO(), force_terminal=True, width=100)
    with counting("solving [x]", console=term) as progress:
        progress(5, 10)
        progress(10, 10)
    shown = term.file.getvalue()
    assert "solving [x]" in shown and "10/10" in shown


@pytest.mark.parametrize(("command", "module", "first"), [
    (["analyze", "fourbar_paper001.toml"], "_planar", "solving 361 positions"),
    (["balance", "fourbar_paper001.toml"], "balance", "balancing"),
    (["reactions", "loom_fourbar_spatial.toml"], "reactions",
     "solving the spatial reactions at 360 positions"),
    (["swashplate", "analyze", "swashplate_1.toml"], "swashplate", "solving 361 rotor angles"),
    (["synthesize", "function", "synthesis_tasks.toml"], "synthesize", "function synthesis"),
])
def test_every_step_of_a_command_is_under_a_progress_bar(command, module, first, tmp_path,
                                                         capsys, monkeypatch):
    """The commands that took more than 2 s without a bar (balance, reactions, swash-plate
    analyze) show one, as analyze does: the solve, then every file written (each output file
    of the folder is named by a step)."""
    import contextlib
    import importlib

    mod = importlib.import_module(f"linkwork.cli.{module}")
    named: list[str] = []

    @contextlib.contextmanager
    def record(total, *, console):
        yield named.append

    monkeypatch.setattr(mod, "steps", record)
    *cmd, name = command
    out = tmp_path / "out"
    assert main([*cmd, str(EXAMPLES / name), "--out", str(out)]) == 0
    capsys.readouterr()
    assert named[0] == first
    text = " ".join(named)
    files = [p.name for p in out.iterdir() if p.name != "linkwork-run.json"]
    assert files
    for f in files:  # each file named by a step (a plot "drawing ...", the rest "writing ...")
        stem = f.rsplit(".", 1)[0]
        assert (stem in text or f in text or (module == "balance" and f.endswith(".png"))
                or (f.startswith("design_") and "design files" in text)), f


def test_the_tolerance_study_bar_stays_out_of_stdout(tmp_path, capsys):
    """Its progress bar was drawn on the command's stdout console, so a piped stdout got a line
    'tolerance study ━━━ 500/500' among the tables; it is on a terminal's stderr now, like
    every other bar."""
    assert main(["reactions", str(EXAMPLES / "loom_fourbar_spatial.toml"), "--no-plots",
                 "--tolerance-study", "50", "--out", str(tmp_path / "o")]) == 0
    out = capsys.readouterr()
    assert "tolerance study: peaks over the cycle, N = 50" in out.out
    bar = re.compile(r"tolerance study ━+ \d+/\d+")
    assert not bar.search(out.out) and not bar.search(out.err) and "50/50" not in out.out
