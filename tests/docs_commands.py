"""Every shell command the documentation shows runs as written.

Reads README.md and docs/*.md in order and runs, in one scratch folder per document (with the
project's examples/ copied in, so that files made by one command are there for the next):
  - the lines of ```sh blocks (continuations joined, comments dropped), and
  - the `$ ` lines of ```text blocks (a session shown with its output).
`build/carom` is the carom under test. A command must exit 0, except one whose shown output is
`carom: error: ...`: it must then exit 2 with that very message. Commands that only set up (make ...) or take hours (the validation scripts
that regenerate docs/validation.md's tables, the fuzzers, a full rebuild) are listed in NOT_RUN
with the reason: a new command in the docs is run unless someone says here why not.

Usage: docs_commands.py SOURCE_DIR CAROM_EXE [PYTHON_MODULE_DIR]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# (a pattern of commands not run, why)
NOT_RUN = [
    (r"^make (demo|test|build|bench|fuzz|fuzz-checkpoint)\b", "sets up or rebuilds the project"),
    (r"^(nice -n \d+ )?(/usr/bin/)?python3 scripts/validate_", "regenerates a validation table: hours"),
    (r"^(/usr/bin/)?python3 scripts/decorrelation\.py", "the decorrelation study: 16 CPU minutes"),
    (r"^/usr/bin/python3 bench/run_bench.py", "the benchmark table: many minutes"),
    (r"^cmake ", "a full rebuild in another folder"),
    (r"^/tmp/b/", "binaries of that rebuild"),
    (r"^for f in tests/fuzz/", "replays the fuzzers' findings against that rebuild"),
    (r"soak\.txt", "the soak test: 10 hours"),
    (r"^build/carom run gas\.txt 5000 .*--checkpoint", "a run meant to be stopped by Ctrl-C"),
    (r"^build/carom run --resume run\.ckpt", "resumes the run above"),
    (r"^build/carom sweep examples/hard_disk_loop\.toml (?!.*--dry-run)",
     "the hard-disk loop at N = 256^2: a day on 2 cores"),
    (r"^(/usr/bin/)?python3 scripts/plot_loop\.py", "draws that loop's results"),
]

# Open MPI refuses to start as root unless told that it is meant (a CI machine runs as root); a
# user's shell needs neither.
MPI_AS_ROOT = ({"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
               if os.geteuid() == 0 else {})


def commands(text):
    """The commands of one document, in order, each with the error it is shown to give (or None)."""
    for kind, body in re.findall(r"```(\w*)\n(.*?)```", text, re.S):
        if kind == "sh":
            joined = re.sub(r"\\\n\s*", " ", body)
            for line in joined.splitlines():
                line = re.sub(r"\s+#.*$", "", line).strip()
                if line and not line.startswith("#"):
                    yield line, None
        elif kind == "text":
            lines = body.splitlines()
            for i, line in enumerate(lines):
                if line.startswith("$ "):
                    shown = lines[i + 1] if i + 1 < len(lines) else ""
                    yield line[2:].strip(), shown if shown.startswith("carom: error:") else None


def reason_not_run(command):
    for pattern, why in NOT_RUN:
        if re.search(pattern, command):
            return why
    return None


def main():
    source, carom = Path(sys.argv[1]), Path(sys.argv[2]).resolve()
    # The Python examples import the module the build assembled.
    python_path = str(Path(sys.argv[3]).resolve()) if len(sys.argv) > 3 else ""
    documents = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    failures, ran, skipped = [], 0, 0
    for document in documents:
        with tempfile.TemporaryDirectory(prefix="carom-docs-") as folder:
            shutil.copytree(source / "examples", Path(folder) / "examples")
            (Path(folder) / "build").mkdir()
            os.symlink(carom, Path(folder) / "build" / "carom")
            for command, error in commands(document.read_text()):
                if reason_not_run(command):
                    skipped += 1
                    continue
                ran += 1
                done = subprocess.run(["bash", "-c", command], cwd=folder, capture_output=True,
                                      text=True, timeout=600,
                                      env={**os.environ, **MPI_AS_ROOT, "PYTHONPATH": python_path})
                if error is not None:
                    if done.returncode != 2 or done.stderr.strip() != error:
                        failures.append(f"{document.name}: {command}\n  shown: {error}\n  "
                                        f"got (exit {done.returncode}): {done.stderr.strip()}")
                elif done.returncode != 0:
                    failures.append(f"{document.name}: {command}\n  exit {done.returncode}: "
                                    f"{done.stderr.strip()[:500]}")
    print(f"ran {ran} documented commands, {skipped} listed as not run")
    for failure in failures:
        print("FAILED", failure)
    if ran == 0:
        print("no commands found: is SOURCE_DIR right?")
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
