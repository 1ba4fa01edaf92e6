"""The Python examples run as docs/python.md shows them."""
import os
import pathlib
import subprocess
import sys

SOURCE = pathlib.Path(os.environ.get("CAROM_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
EXAMPLES = SOURCE / "examples" / "python"


def run_example(name, *args, cwd):
    return subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=cwd, check=True,
                          capture_output=True, text=True).stdout


def test_quickstart_prints_the_command_lines_table(tmp_path):
    out = run_example("quickstart.py", cwd=tmp_path)
    cli = subprocess.run([os.environ["CAROM_EXE"], "run", str(SOURCE / "examples" / "walls_only.txt"),
                          "20"], check=True, capture_output=True, text=True).stdout
    assert out.startswith(cli)
    assert "4 collisions by t = 20.0" in out


def test_equation_of_state_writes_its_plot(tmp_path):
    png = tmp_path / "eos.png"
    out = run_example("equation_of_state.py", "--n", "64", "--equilibrate", "1", "--measure", "2",
                      "-o", str(png), cwd=tmp_path)
    rows = [line.split() for line in out.splitlines() if line.strip()[:1] == "0"]
    assert len(rows) == 7
    for eta, measured, henderson, collisions in rows:
        assert float(measured) > 1.0 and int(collisions) > 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
