"""Every shell command the documentation shows runs as written, and prints what it is shown to print.

Reads README.md and docs/*.md in order and runs, in one scratch folder per document (with the
project's examples/ and scripts/ copied in, so that files made by one command are there for the next):
  - the lines of ```sh blocks (continuations joined, comments dropped), and
  - the `$ ` lines of ```text blocks (a session shown with its output).
`build/carom` is the carom under test. A command must exit 0, except one whose shown output is
`carom: error: ...`: it must then exit 2 with that very message. Commands that only set up (make ...) or take hours (the validation scripts
that regenerate docs/validation.md's tables, the fuzzers, a full rebuild) are listed in NOT_RUN
with the reason: a new command in the docs is run unless someone says here why not.

The output a ```text block shows after a `$ ` command (its lines up to the next `$ ` line or the
block's end) must be what the command printed: its stdout, followed by its stderr when the docs
show a `carom: ...` message. Two conventions shorten what is shown:
  - a line ending in `...` matches any printed line that starts with what precedes the `...`
    (a long number: `80.215763...`);
  - a line that is only `...` (indentation aside) stands for any number of printed lines,
    none included (lines omitted).
A block whose output depends on the clock or the machine (wall seconds, events per second, the
paths of temporary folders) is not compared when the line just before its opening fence is
    <!-- output varies -->
(its commands still run and must still succeed). Use it sparingly: carom's runs are bit-for-bit
reproducible, so a difference between two runs is a clock or machine field, never noise.

After a change that alters what commands print, regenerate the shown outputs in place with
`make docs-outputs` (after `make build`; it runs
    /usr/bin/python3 tests/docs_commands.py --update . build/carom build/python
from the project folder): it runs the same commands the same way and rewrites
the shown lines that differ, keeping `...` truncations and omissions that still match and leaving
`<!-- output varies -->` blocks alone. Run twice, the second run changes nothing.

Usage: docs_commands.py [--update] SOURCE_DIR CAROM_EXE [PYTHON_MODULE_DIR]
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
    (r"^make (demo|test|build|bench|fuzz|fuzz-checkpoint|docs-outputs)\b", "sets up or rebuilds the project"),
    (r"^(nice -n \d+ )?(/usr/bin/)?python3 scripts/validate_", "regenerates a validation table: hours"),
    (r"^(/usr/bin/)?python3 scripts/decorrelation\.py", "the decorrelation study: 16 CPU minutes"),
    (r"^/usr/bin/python3 bench/run_bench.py", "the benchmark table: many minutes"),
    (r"^cmake ", "a full rebuild in another folder"),
    (r"^/tmp/b/", "binaries of that rebuild"),
    (r"^for f in tests/fuzz/", "replays the fuzzers' findings against that rebuild"),
    (r"soak\.txt", "the soak test: 10 hours"),
    (r"^build/carom run gas\.txt 5000 .*--checkpoint", "a run meant to be stopped by Ctrl-C"),
    (r"^build/carom run --resume run\.ckpt", "resumes the run above"),
    (r"^build/carom sweep examples/hard_disk_loop(_fluid)?\.toml (?!.*--dry-run)",
     "the hard-disk loop at N = 256^2: eight hours on one core"),
    (r"^(/usr/bin/)?python3 scripts/plot_loop\.py", "draws that loop's results"),
    (r"^(/usr/bin/)?python3 scripts/series_tau\.py (x720|d720|md720)/",
     "reads that loop's runs at 0.720: hours of CPU each"),
    (r"^build/carom analyze (x720|md720)/frames\.gsd", "analyses those runs' frames"),
]

# Open MPI refuses to start as root unless told that it is meant (a CI machine runs as root); a
# user's shell needs neither.
MPI_AS_ROOT = ({"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}
               if os.geteuid() == 0 else {})


VARIES = "<!-- output varies -->"


class Shown:
    """The output a ```text block shows after one command: its lines, and where they sit in the
    document (character offsets of the first shown line's start and of the last one's end)."""

    def __init__(self, lines, start, end, compared):
        self.lines, self.start, self.end, self.compared = lines, start, end, compared


def commands(text):
    """The commands of one document, in order, each with the error it is shown to give (or None)
    and, for a `$ ` command of a ```text block, the output shown after it (a Shown, else None)."""
    for block in re.finditer(r"```(\w*)\n(.*?)```", text, re.S):
        kind, body = block.group(1), block.group(2)
        if kind == "sh":
            joined = re.sub(r"\\\n\s*", " ", body)
            for line in joined.splitlines():
                line = re.sub(r"\s+#.*$", "", line).strip()
                if line and not line.startswith("#"):
                    yield line, None, None
        elif kind == "text":
            before = text[:block.start()].rstrip("\n").rsplit("\n", 1)[-1].strip()
            compared = before != VARIES
            lines, offset, starts = body.splitlines(), block.start(2), []
            for line in lines:
                starts.append(offset)
                offset += len(line) + 1
            starts.append(offset)
            for i, line in enumerate(lines):
                if line.startswith("$ "):
                    j = i + 1
                    while j < len(lines) and not lines[j].startswith("$ "):
                        j += 1
                    shown = Shown(lines[i + 1:j], starts[i + 1], starts[j], compared)
                    first = shown.lines[0] if shown.lines else ""
                    yield (line[2:].strip(), first if first.startswith("carom: error:") else None,
                           shown)


def is_gap(shown_line):
    return shown_line.strip() == "..."


def line_matches(shown_line, printed_line):
    if shown_line.endswith("..."):
        return printed_line.startswith(shown_line[:-3])
    return shown_line == printed_line


def matches(shown, printed):
    """Whether the printed lines are what the shown lines show (`...` conventions above)."""
    if not shown:
        return not printed
    if is_gap(shown[0]):
        return any(matches(shown[1:], printed[k:]) for k in range(len(printed) + 1))
    return bool(printed) and line_matches(shown[0], printed[0]) and matches(shown[1:], printed[1:])


def first_difference(shown, printed):
    """(shown line, printed line) where the two first part, walking both in step (a gap skips to
    the printed line that matches the next shown one)."""
    i = k = 0
    while i < len(shown):
        if is_gap(shown[i]):
            i += 1
            if i == len(shown):
                return None
            while k < len(printed) and not line_matches(shown[i], printed[k]):
                k += 1
            if k == len(printed):
                return shown[i], "(no such line printed after the omitted ones)"
        if k == len(printed):
            return shown[i], "(nothing more printed)"
        if not line_matches(shown[i], printed[k]):
            return shown[i], printed[k]
        i, k = i + 1, k + 1
    return ("(nothing more shown)", printed[k]) if k < len(printed) else None


def regenerated(shown, printed):
    """The shown lines rewritten to what was printed: each line that still matches is kept (with
    its `...`), each gap still skips printed lines, every other line becomes the printed one.
    None when the gaps cannot be placed without a person's judgement."""
    if matches(shown, printed):
        return list(shown)
    out, i, k = [], 0, 0
    while i < len(shown):
        if is_gap(shown[i]):
            out.append(shown[i])
            rest = [line for line in shown[i + 1:] if not is_gap(line)]
            if i + 1 == len(shown):
                return out
            if not any(is_gap(line) for line in shown[i + 1:]):
                skip_to = len(printed) - len(rest)    # the lines after the last gap: the tail
            else:
                skip_to = next((m for m in range(k, len(printed))
                                if line_matches(shown[i + 1], printed[m])), None)
            if skip_to is None or skip_to < k:
                return None
            k, i = skip_to, i + 1
            continue
        if k == len(printed):
            i += 1                                     # shown but no longer printed: dropped
            continue
        out.append(shown[i] if line_matches(shown[i], printed[k]) else printed[k])
        i, k = i + 1, k + 1
    return out + printed[k:]


def printed_lines(shown, done):
    """What a command printed, as the shown output is compared with: stdout, then stderr when
    the docs show a `carom: ...` message."""
    out = done.stdout.splitlines()
    if any(line.startswith("carom: ") for line in shown.lines):
        out += done.stderr.splitlines()
    return out


def reason_not_run(command):
    for pattern, why in NOT_RUN:
        if re.search(pattern, command):
            return why
    return None


def main():
    arguments = sys.argv[1:]
    update = "--update" in arguments
    if update:
        arguments.remove("--update")
    source, carom = Path(arguments[0]), Path(arguments[1]).resolve()
    # The Python examples import the module the build assembled.
    python_path = str(Path(arguments[2]).resolve()) if len(arguments) > 2 else ""
    documents = [source / "README.md"] + sorted((source / "docs").glob("*.md"))
    failures, ran, skipped, rewritten = [], 0, 0, []
    for document in documents:
        text = document.read_text()
        listed = list(commands(text))
        if update and not any(shown is not None and shown.compared for _, _, shown in listed):
            continue                                   # nothing shown to rewrite
        edits = []                                     # (start, end, new lines) of shown outputs
        with tempfile.TemporaryDirectory(prefix="carom-docs-") as folder:
            shutil.copytree(source / "examples", Path(folder) / "examples")
            shutil.copytree(source / "scripts", Path(folder) / "scripts")
            (Path(folder) / "build").mkdir()
            os.symlink(carom, Path(folder) / "build" / "carom")
            for command, error, shown in listed:
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
                        continue
                elif done.returncode != 0:
                    failures.append(f"{document.name}: {command}\n  exit {done.returncode}: "
                                    f"{done.stderr.strip()[:500]}")
                    continue
                if shown is None or not shown.compared:
                    continue
                printed = printed_lines(shown, done)
                if update:
                    new = regenerated(shown.lines, printed)
                    if new is None:
                        failures.append(f"{document.name}: {command}\n  cannot place the shown "
                                        f"`...` omissions in the new output: edit by hand")
                    elif new != shown.lines:
                        edits.append((shown.start, shown.end, new))
                else:
                    difference = first_difference(shown.lines, printed)
                    if difference is None and not matches(shown.lines, printed):
                        difference = ("(the shown lines)", "(do not match what was printed)")
                    if difference is not None:
                        failures.append(f"{document.name}: {command}\n  output differs from "
                                        f"what the document shows; first difference:\n"
                                        f"    shown:   {difference[0]}\n"
                                        f"    printed: {difference[1]}")
        if edits:
            for start, end, new in reversed(edits):
                text = text[:start] + "".join(line + "\n" for line in new) + text[end:]
            document.write_text(text)
            rewritten.append(f"{document.name} ({len(edits)} outputs)")
    print(f"ran {ran} documented commands, {skipped} listed as not run")
    if update:
        print("rewrote " + (", ".join(rewritten) if rewritten else "nothing: every shown output "
                            "is what its command prints"))
    for failure in failures:
        print("FAILED", failure)
    if ran == 0:
        print("no commands found: is SOURCE_DIR right?")
        return 1
    if failures and not update:
        print("(after a change that alters what commands print, `make docs-outputs` rewrites the "
              "shown outputs)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
