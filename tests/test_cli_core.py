"""The CLI's failure policy: one line on stderr and exit code 2, never a traceback."""

from linkwork.cli import main


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
