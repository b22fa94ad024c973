"""Hostile and careless inputs through the real command lines: located errors and exit codes, never a traceback,
never a file touched that is not the command's own output."""

from __future__ import annotations

import json
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from orc_rpl.cli import main

ROOT = Path(__file__).resolve().parents[2]


def orc(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str]:
    """Exit code and everything printed (stdout then stderr) of `orc ARGV` run in-process."""
    code = main(list(argv))
    captured = capsys.readouterr()
    text = captured.out + captured.err
    assert "Traceback" not in text and "internal error" not in text, text
    return code, text


def write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


# -- equipment ports and world lines -------------------------------------------------------------


@pytest.mark.parametrize("port", ["spy://loop://?file=PWNED", "socket://127.0.0.1:9", "rfc2217://host:1", "/etc/passwd",
                                  "../x", "/dev/zero", "/dev/shm/x"])
def test_a_port_that_is_no_device_is_a_check_error_at_its_literal(tmp_path, capsys, port) -> None:
    program = write(tmp_path / "p.rpl", f'INSTALL L AS LaserDistance WITH PORT = "{port}"\n')
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and "p.rpl:1:40: attribute PORT of LaserDistance" in text and "is not an equipment port" in text


def test_a_computed_url_port_is_a_sensor_fault_and_touches_no_file(tmp_path, capsys, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)
    program = write(tmp_path / "p.rpl", 'VAR p = "spy://loop://?file=PWNED"\nINSTALL L AS LaserDistance WITH PORT = p\n')
    code, text = orc(capsys, "run", str(program))
    assert code == 1 and "p.rpl:2:1: SensorFault: L: 'spy://loop://?file=PWNED' is not an equipment port" in text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.rpl"]


def test_a_simulated_run_opens_no_device_unless_the_command_line_allows_it(tmp_path, capsys) -> None:
    program = write(tmp_path / "p.rpl", 'INSTALL L AS LaserDistance WITH PORT = "/dev/ttyUSB_none"\n')
    code, text = orc(capsys, "run", str(program))
    assert code == 1 and "this run opens no real device" in text and "--allow-devices" in text
    code, text = orc(capsys, "run", str(program), "--allow-devices")
    assert code == 1 and "cannot open the laser on /dev/ttyUSB_none" in text


def test_a_world_line_must_name_a_yaml_file(tmp_path, capsys) -> None:
    program = write(tmp_path / "p.orl", "# world: /etc/passwd\nprint(1)\n")
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and "p.orl:1:10: the world model '/etc/passwd' must be a YAML file" in text
    assert "root:" not in text


@pytest.mark.parametrize("content", ["password: hunter2\n", "hunter2 [\n", "- hunter2\n", "hunter2: [\n"])
def test_a_file_that_is_not_a_world_is_never_quoted(tmp_path, capsys, content) -> None:
    write(tmp_path / "secret.yaml", content)
    program = write(tmp_path / "p.orl", "# world: secret.yaml\nprint(1)\n")
    for argv in (["check", str(program)], ["run", str(program)], ["convert", str(program)]):
        code, text = orc(capsys, *argv)
        assert code == 2 and "not a world model" in text and "hunter2" not in text


# -- inputs are never outputs -------------------------------------------------------------------


def test_a_run_never_writes_its_summary_over_its_program(tmp_path, capsys) -> None:
    program = write(tmp_path / "self.rpl", 'PRINT "ran"\n')
    link = tmp_path / "other.json"
    link.symlink_to(program)
    for target in (program, link):
        code, text = orc(capsys, "run", str(program), "--summary-json", str(target))
        assert code == 2 and "is also the input FILE" in text and "ran" not in text
    assert program.read_text() == 'PRINT "ran"\n'


def test_a_hard_link_to_the_program_is_the_same_file(tmp_path, capsys) -> None:
    program = write(tmp_path / "self.rpl", "PRINT 1\n")
    os.link(program, tmp_path / "alias.npz")
    code, text = orc(capsys, "run", str(program), "--log", str(tmp_path / "alias.npz"))
    assert code == 2 and "is also the input FILE" in text


def _offline_copy(tmp_path: Path) -> Path:
    shutil.copytree(ROOT / "worlds", tmp_path / "worlds")
    (tmp_path / "programs" / "offline").mkdir(parents=True)
    return Path(shutil.copy(ROOT / "programs" / "offline" / "spot_welding.orl", tmp_path / "programs" / "offline"))


def test_convert_refuses_outputs_that_are_inputs_or_each_other(tmp_path, capsys) -> None:
    program = _offline_copy(tmp_path)
    world = tmp_path / "worlds" / "spot_welding.yaml"
    before = world.read_text(), program.read_text()
    out = str(tmp_path / "out.rpl")
    for extra, message in ((["-o", out, "--online-world", out], "is also the output -o"),
                           (["-o", out, "--online-world", str(world)], "is also the input the world model"),
                           (["-o", out, "--online-world", str(program)], "is also the input FILE")):
        code, text = orc(capsys, "convert", str(program), *extra)
        assert code == 2 and message in text
    assert (world.read_text(), program.read_text()) == before and not Path(out).exists()


def test_fmt_write_on_a_symlink_rewrites_its_target(tmp_path, capsys) -> None:
    target = write(tmp_path / "real.rpl", "PRINT   1\n")
    link = tmp_path / "link.rpl"
    link.symlink_to(target)
    code, _ = orc(capsys, "fmt", "--write", str(link))
    assert code == 0 and link.is_symlink() and target.read_text() == "PRINT 1\n"


def test_new_outputs_get_the_users_umask(tmp_path, capsys) -> None:
    program = _offline_copy(tmp_path)
    old = os.umask(0o027)
    try:
        code, _ = orc(capsys, "convert", str(program), "-o", str(tmp_path / "out.rpl"))
    finally:
        os.umask(old)
    assert code == 0 and stat.S_IMODE((tmp_path / "out.rpl").stat().st_mode) == 0o640


def test_an_output_folder_that_does_not_exist_is_refused_before_the_run(tmp_path, capsys) -> None:
    program = write(tmp_path / "p.rpl", 'PRINT "ran"\n')
    code, text = orc(capsys, "run", str(program), "--plot", str(tmp_path / "no" / "plot.png"))
    assert code == 2 and "--plot: the folder of" in text and "ran" not in text
    code, text = orc(capsys, "run", str(program), "--log", str(tmp_path))
    assert code == 2 and "is a directory" in text


# -- one error boundary -------------------------------------------------------------------------


@pytest.mark.parametrize("text", [
    "IF TRUE THEN\n" * 400 + "PRINT 1\n" + "ENDIF\n" * 400,
    "PRINT " + "+".join(["1"] * 2000) + "\n",
    "PRINT " + "NOT " * 1000 + "TRUE\n",
], ids=["400 nested IFs", "2000 additions", "1000 NOTs"])
def test_deep_nesting_is_a_located_error_in_every_command(tmp_path, capsys, text) -> None:
    program = write(tmp_path / "deep.rpl", text)
    for command in ("check", "fmt", "run", "diff"):
        argv = [command, str(program)] + ([str(program)] if command == "diff" else [])
        code, out = orc(capsys, *argv)
        assert code == 2 and "nested too deeply (more than 200 levels" in out and "deep.rpl:" in out


@pytest.mark.parametrize("text, printed", [
    ("IF TRUE THEN\n" * 45 + "PRINT " + "+".join(["1"] * 100) + "\n" + "ENDIF\n" * 45, "100"),
    ("IF TRUE THEN\n" * 99 + "PRINT 1\n" + "ENDIF\n" * 99, "1"),
    ("PRINT " + "+".join(["1"] * 198) + "\n", "198"),
], ids=["45 IFs around 100 terms", "99 IFs", "198 terms"])
def test_nesting_below_the_limit_checks_formats_runs_and_converts(tmp_path, capsys, text, printed) -> None:
    program = write(tmp_path / "ok.rpl", text)
    assert orc(capsys, "check", str(program))[0] == 0
    assert orc(capsys, "fmt", "--check", str(program))[0] in (0, 1)
    code, out = orc(capsys, "run", str(program))
    assert code == 0 and out.startswith(printed + "\n")
    assert orc(capsys, "convert", str(program), "-o", str(tmp_path / "ok.orl"), "--world", str(tmp_path / "w.yaml"))[0] == 0


def test_an_integer_literal_over_4300_digits_is_a_syntax_error(tmp_path, capsys) -> None:
    program = write(tmp_path / "big.rpl", "PRINT " + "9" * 5000 + "\n")
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and "big.rpl:1:7: integer literal with 5000 digits is too long (at most 4300)" in text


@pytest.mark.parametrize("literal", ["9" * 400 + "mm", "1e400mm", "1e999"])
def test_a_number_literal_that_is_not_finite_is_a_syntax_error(tmp_path, capsys, literal) -> None:
    program = write(tmp_path / "big.rpl", f"PRINT {literal}\n")
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and "big.rpl:1:7: number literal" in text and "is too large (not a finite number)" in text


def test_sixteen_thousand_stray_endifs_print_fifty_errors_and_a_count(tmp_path, capsys) -> None:
    program = write(tmp_path / "endif.rpl", "ENDIF\n" * 16000)
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and text.count("endif.rpl:") == 51 and "15950 more errors not shown" in text and "16000 errors in 1 of 1 file" in text


@pytest.mark.parametrize("value, message", [
    ("[.nan, 0, 100mm, 0, 0, 0]", "'.nan' is not a number"),
    ("[1e999, 0, 100mm, 0, 0, 0]", "'1e999' is not a finite number"),
])
def test_world_values_are_validated_at_their_line_and_column(tmp_path, capsys, value, message) -> None:
    program = _offline_copy(tmp_path)
    world = tmp_path / "worlds" / "spot_welding.yaml"
    world.write_text(world.read_text().replace("pose: [0, 0, 100mm, 0, 0, 0]", f"pose: {value}"))
    code, text = orc(capsys, "check", str(program))
    assert code == 2 and "spot_welding.yaml:30:12: " + message in text


@pytest.mark.parametrize("replacement, message", [
    ("colour: [1m, 0, 0]", "spot_welding.yaml:18:16: a colour value is a plain number from 0 to 1, got '1m'"),
    ("colour: grey\n    soft:\n      n: 0x1Fz", None),
    ("colour: grey\n    soft:\n      n: .inf", "spot_welding.yaml:20:10: '.inf' is not a number"),
    ("colour: gr\x07ey", "spot_welding.yaml:18:17: character #x0007 is not allowed in a YAML file"),
    ("colour: " + "[" * 3000 + "]" * 3000, "spot_welding.yaml:18:"),
])
def test_mistyped_world_values_are_located_errors(tmp_path, capsys, replacement, message) -> None:
    program = _offline_copy(tmp_path)
    world = tmp_path / "worlds" / "spot_welding.yaml"
    world.write_text(world.read_text().replace("colour: grey", replacement, 1))
    code, text = orc(capsys, "check", str(program))
    assert code in (0, 2) and (message is None or message in text)


def test_special_and_binary_files_are_refused_before_reading(tmp_path, capsys) -> None:
    fifo = tmp_path / "fifo.rpl"
    os.mkfifo(fifo)
    zero = tmp_path / "zero.rpl"
    zero.symlink_to("/dev/zero")
    binary = tmp_path / "bin.rpl"
    binary.write_bytes(b"PRINT 1\n\x00\x01\x02")
    code, text = orc(capsys, "check", str(fifo), str(zero), str(binary))
    assert code == 2
    assert "cannot read '" + str(fifo) + "': it is a pipe (FIFO)" in text
    assert "cannot read '" + str(zero) + "': it is a device" in text
    assert "a binary file, not text (a NUL byte at line 2, column 1)" in text


def test_a_binary_world_is_refused_in_run_and_diff(tmp_path, capsys) -> None:
    program = _offline_copy(tmp_path)
    world = tmp_path / "bin.yaml"
    world.write_bytes(b"robot:\n\xff\xfe\x00")
    for argv in (["run", str(program), "--world", str(world)], ["diff", str(program), str(program), "--world", str(world)]):
        code, text = orc(capsys, *argv)
        assert code == 2 and "cannot read world model" in text and "binary file" in text


@pytest.mark.parametrize("sidecar, message", [
    (b"events:\n  - \x00\x01", "binary file"),
    (b"events: " + b"[" * 200 + b"]" * 200, "nested too deeply"),
    (b"weld_guns:\n  - close: [1, 2]\n", "IO script"),
    (b"events:\n  - at: " + b"9" * 5000 + b"\n", "IO script"),
])
def test_a_bad_sidecar_is_a_usage_error_naming_it(tmp_path, capsys, sidecar, message) -> None:
    program = write(tmp_path / "p.rpl", "PRINT 1\n")
    (tmp_path / "p.sim.yaml").write_bytes(sidecar)
    code, text = orc(capsys, "run", str(program))
    assert code == 2 and "p.sim.yaml" in text and message in text


def test_a_world_object_on_the_flange_used_as_a_value_is_no_traceback(tmp_path, capsys) -> None:
    program = _offline_copy(tmp_path)
    used = write(program.with_name("used.orl"), "# world: ../../worlds/spot_welding.yaml\nx = weldgun\nprint(weldgun)\n")
    for command in ("check", "run", "convert"):
        code, _ = orc(capsys, command, str(used))
        assert code in (0, 1, 2)


@pytest.mark.parametrize("command", ["fmt", "run"])
def test_a_closed_reader_is_no_traceback(tmp_path, command) -> None:
    program = write(tmp_path / "many.rpl", "".join(f"PRINT {i}\n" for i in range(30000)))
    pipeline = f"{sys.executable} -m orc_rpl {command} {program} | head -1"
    done = subprocess.run(["bash", "-c", "set -o pipefail; " + pipeline], capture_output=True, text=True, timeout=300)
    assert done.stdout in ("PRINT 0\n", "0\n")
    assert "Traceback" not in done.stderr and "BrokenPipe" not in done.stderr and "internal error" not in done.stderr


# -- bounded run time ---------------------------------------------------------------------------


@pytest.mark.parametrize("text, message", [
    ("WAIT 100000s\n", "p.rpl:1:1: WAIT of 100000 s is longer than the longest allowed, 86400 s"),
    ("WAIT UNTIL FALSE TIMEOUT 1e300s\n", "TIMEOUT of 1e+300 s is longer than the longest allowed"),
    ("MOVE ARM TO HERE WITH TIME = 1e9s\n", "p.rpl:1:1: MOVE: TIME of 1000000000 s is longer than the longest allowed"),
    ("FOR i FROM 1e300 TO 1e300 + 1 DO\nENDFOR\n", "p.rpl:1:1: FOR cannot advance: 1e+300 + STEP 1 is 1e+300 again"),
    ("FOR i FROM 0 TO 1 STEP 1e-300 DO\nENDFOR\n", "p.rpl:1:1: FOR would run about 1e+300 times"),
    ("VAR i = 0\nWHILE TRUE DO\n  i = i + 1\nENDWHILE\n", "statements ran without the robot moving or time passing"),
    ("WHILE TRUE DO\nENDWHILE\n", "p.rpl:1:1: 1000 statements ran without the robot moving"),
])
def test_runs_that_would_never_end_are_errors_at_their_statement(tmp_path, capsys, text, message) -> None:
    program = write(tmp_path / "p.rpl", text)
    code, out = orc(capsys, "run", str(program), "--statement-budget", "1000")
    assert code == 1 and message in out


def test_a_timeout_stops_the_robot_and_keeps_the_summary_and_the_log(tmp_path, capsys) -> None:
    program = write(tmp_path / "p.rpl", 'PRINT "start"\nWAIT 80000s\nPRINT "never"\n')
    summary, log = tmp_path / "s.json", tmp_path / "l.npz"
    code, text = orc(capsys, "run", str(program), "--timeout", "2", "--summary-json", str(summary), "--log", str(log))
    result = json.loads(summary.read_text())
    assert code == 1 and "interrupted by --timeout 2 s (simulated)" in text and "never" not in text
    assert result["status"] == "interrupted" and result["prints"] == ["start"] and 2.0 <= result["cycle_time_s"] < 2.1
    assert log.stat().st_size > 0


@pytest.mark.parametrize("value", ["-1", "0", "inf", "nan", "x"])
def test_a_bad_timeout_is_a_usage_error(tmp_path, capsys, value) -> None:
    program = write(tmp_path / "p.rpl", "PRINT 1\n")
    with pytest.raises(SystemExit) as exit_:
        main(["run", str(program), "--timeout", value])
    assert exit_.value.code == 2 and "--timeout" in capsys.readouterr().err


@pytest.mark.parametrize(("signal_name", "said", "code"), [("SIGINT", "Ctrl-C", 130), ("SIGTERM", "SIGTERM", 143)])
def test_ctrl_c_or_sigterm_stops_the_robot_and_writes_the_summary_and_log_as_interrupted(tmp_path, signal_name: str,
                                                                                       said: str, code: int) -> None:
    import signal

    program = write(tmp_path / "p.rpl", 'PRINT "start"\nWAIT 80000s\n')
    summary, log = tmp_path / "s.json", tmp_path / "l.npz"
    child = subprocess.Popen([sys.executable, "-m", "orc_rpl", "run", str(program), "--realtime", "--summary-json", str(summary),
                              "--log", str(log)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert child.stdout is not None and child.stdout.readline() == "start\n"
    child.send_signal(getattr(signal, signal_name))
    _, err = child.communicate(timeout=120)
    assert child.returncode == code and f"interrupted by {said}" in err and "Traceback" not in err
    assert json.loads(summary.read_text())["status"] == "interrupted" and log.stat().st_size > 0


# -- rendering only when asked ------------------------------------------------------------------


def test_a_run_loads_no_opengl() -> None:
    script = ("import sys\nfrom orc_rpl.cli import main\ncode = main(['run', sys.argv[1]])\n"
              "print('GL', 'OpenGL' in sys.modules, code)\n")
    env = {key: value for key, value in os.environ.items() if key != "MUJOCO_GL"}
    program = ROOT / "programs" / "online" / "thesis_7_3_online_simple.rpl"
    done = subprocess.run([sys.executable, "-c", script, str(program)], capture_output=True, text=True, env=env, timeout=300)
    assert done.stdout.strip().endswith("GL False 0"), done.stderr


def test_no_backend_names_the_packages_and_the_values_to_try(monkeypatch) -> None:
    from orc_rpl.errors import UsageError
    from orc_rpl.plant import gl

    monkeypatch.setattr(gl, "_available", lambda: [])
    monkeypatch.setitem(gl._state, "backend", "")
    monkeypatch.setitem(gl._state, "chosen_by_us", True)
    with pytest.raises(UsageError) as error:
        gl.request_rendering()
    message = str(error.value)
    assert "libegl1" in message and "libosmesa6" in message and "MUJOCO_GL=egl" in message and "MUJOCO_GL=osmesa" in message


def test_the_pendant_refuses_missing_folders_and_unreadable_programs_before_the_screen(tmp_path, capsys) -> None:
    fifo = tmp_path / "fifo.rpl"
    os.mkfifo(fifo)
    binary = tmp_path / "bin.rpl"
    binary.write_bytes(b"PRINT 1\x00")
    for path, message in ((tmp_path / "none" / "p.rpl", "does not exist"), (fifo, "not a regular file"),
                          (binary, "bin.rpl")):
        code, text = orc(capsys, "pendant", str(path))
        assert code == 2 and message in text


def test_an_output_that_is_a_device_is_refused(tmp_path, capsys) -> None:
    program = write(tmp_path / "p.rpl", "PRINT 1\n")
    code, text = orc(capsys, "run", str(program), "--summary-json", "/dev/null")
    assert code == 2 and "'/dev/null' is not a regular file" in text and os.path.exists("/dev/null")


def test_a_conversion_killed_between_its_renames_is_detected_by_the_next_command(tmp_path, capsys, monkeypatch) -> None:
    from orc_rpl.commands import outputs

    program = _offline_copy(tmp_path)
    online, world = tmp_path / "out.rpl", tmp_path / "online.yaml"
    argv = ["convert", str(program), "-o", str(online), "--online-world", str(world)]
    real_replace, calls = os.replace, []

    def killed_after_first(source, target):  # type: ignore[no-untyped-def]
        calls.append(target)
        if len(calls) == 3:  # the list of outputs, the program, then the kill before the world
            raise KeyboardInterrupt
        real_replace(source, target)
    monkeypatch.setattr(outputs.os, "replace", killed_after_first)
    assert main(argv) == 130 and online.exists() and not world.exists()
    monkeypatch.setattr(outputs.os, "replace", real_replace)
    capsys.readouterr()
    code, text = orc(capsys, "check", str(online))
    assert code == 2 and "may be out of step with the files written with it" in text and ".out.rpl.converting" in text
    code, _ = orc(capsys, *argv)
    assert code == 0 and world.exists() and not (tmp_path / ".out.rpl.converting").exists()
    assert orc(capsys, "check", str(online))[0] == 0
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")) == []


@pytest.mark.parametrize("script, where, message", [
    ("events:\n  - at: 1s\n    set: DigIn[1]\n    value: 1\n  - at: [1]\n    set: DigIn[2]\n", "5:5", "IO script event 2: not a number"),
    ("weld_guns:\n  - close: [1, 2]\n", "2:5", "IO script weld gun 1: a weld gun has close"),
], ids=["event", "weld-gun"])
def test_a_sidecar_mistake_is_reported_at_its_line_and_column(tmp_path, monkeypatch, capsys, script, where, message) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.rpl").write_text("WAIT 0.1s\n", encoding="utf-8")
    (tmp_path / "p.sim.yaml").write_text(script, encoding="utf-8")
    assert main(["run", "p.rpl", "--plant", "ideal"]) == 2
    err = capsys.readouterr().err
    assert f"p.sim.yaml:{where}: {message}" in err and "Traceback" not in err
