"""scripts/plot_loop.py: the loop's table from a sweep's results.csv or from the table of chains
in docs/data/, each packing's chains averaged with an error no smaller than their scatter."""

import re
import subprocess
import sys

from conftest import SOURCE_DIR

SCRIPT = SOURCE_DIR / "scripts" / "plot_loop.py"
CHAINS = SOURCE_DIR / "docs" / "data" / "hard_disk_loop_runs.csv"


def plot(*args):
    return subprocess.run([sys.executable, SCRIPT, *map(str, args)], capture_output=True,
                          text=True)


def rows(printed):
    """{packing: cells} of the printed Markdown table."""
    table = {}
    for line in printed.splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        if re.fullmatch(r"0\.\d{3}", cells[0]):
            table[cells[0]] = cells[1:]
    return table


def test_chains_of_a_packing_are_averaged_with_their_scatter(tmp_path):
    chains = tmp_path / "chains.csv"
    chains.write_text("# a comment line\n"
                      "phi,start,seed,from,to,beta_p,error\n"
                      "0.704,lattice,2,12000,18000,9.200,0.001\n"
                      "0.704,fluid,4,12000,18000,9.180,0.001\n"
                      "0.716,fluid,3,12000,18000,9.17791,0.002\n")
    done = plot(chains, "-o", tmp_path / "loop.svg")
    assert done.returncode == 0, done.stderr
    table = rows(done.stdout)
    # Two chains 0.02 apart with errors of 0.001: the error is their scatter's, 0.01, not the
    # 0.0007 of their errors combined.
    assert table["0.704"][:3] == ["9.19000 +- 0.01000", "2", "12000-18000"]
    # Their scatter is sqrt(chi2) = 14.14 times their errors: so is every chain's error taken to
    # be, the one chain at 0.716 too.
    assert "multiplied by 14.14" in done.stdout
    assert table["0.716"][0] == "9.17791 +- 0.02828"
    assert "(+0.0)" in table["0.716"][3]  # Bernard and Krauth's 9.17791 at 0.716
    assert "2 of 2 within two combined errors" in done.stdout
    assert (tmp_path / "loop.svg").stat().st_size > 0
    # The factor from the packings 0.71 to 0.72 only: none there is measured twice.
    apart = plot(chains, "-o", tmp_path / "loop.svg", "--scale-from", "0.71", "0.72")
    assert rows(apart.stdout)["0.716"][0] == "9.17791 +- 0.00200"
    assert "multiplied" not in apart.stdout


def test_a_sweeps_results_give_the_same_table(tmp_path):
    results = tmp_path / "results.csv"
    z = 9.17791 * 3.141592653589793 / (4 * 0.716)
    results.write_text("phi,seed,status,Z,Z_error\n"
                       f"0.716,1,done,{z!r},0.001\n"
                       "0.718,1,running,,\n")
    done = plot(results, "-o", tmp_path / "loop.svg")
    assert done.returncode == 0, done.stderr
    table = rows(done.stdout)
    assert list(table) == ["0.716"] and table["0.716"][0].startswith("9.17791 +- ")
    assert "1 tasks not done" in done.stdout


def test_the_projects_table_of_chains_covers_the_loop(tmp_path):
    done = plot(CHAINS, "-o", tmp_path / "loop.svg")
    assert done.returncode == 0, done.stderr
    assert list(rows(done.stdout)) == [f"{0.698 + 0.002 * i:.3f}" for i in range(12)]
