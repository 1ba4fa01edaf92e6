"""Reads the published hard-disk pressures of docs/data/historic_disks/ (HistoricDisks' format).

A file is a header of `Field = value` lines, then groups, each after a line of two commas:
two lines of tags (`Sampling method`, `Pressure calculation method`, `N`, `Aspect ratio`,
`Boundary condition`, `X unit`, `Y unit`, `type`) and rows `x, y, error`. Used by
validate_small_n.py and plot_loop.py; `python3 scripts/historic_disks.py FILE` lists the groups.
"""
import csv
import os
import sys

DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "data",
                    "historic_disks")


def read_groups(path):
    """The groups of one file: [{"tags": {name: value}, "points": [(x, y, err)]}], in file order."""
    groups = []
    current = None
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.reader(f):
            cells = [c.strip() for c in row]
            if not any(cells):
                current = None
                continue
            if all("=" in c for c in cells if c):
                if groups and current is None and not groups[-1]["points"] \
                        and groups[-1]["tags"]:
                    current = groups[-1]
                if current is None:
                    current = {"tags": {}, "points": []}
                    groups.append(current)
                for c in cells:
                    if c:
                        key, _, value = c.partition("=")
                        current["tags"][key.strip()] = value.strip()
                continue
            if current is None:
                raise ValueError(f"{path}: a data row outside a group: {row}")
            x, y = float(cells[0]), float(cells[1])
            err = float(cells[2]) if len(cells) > 2 and cells[2] else 0.0
            current["points"].append((x, y, err))
    # The header is a group of tags with no points: drop it (and any like it).
    return [g for g in groups if g["points"]]


def n_value(text):
    """N as written in a file ("870", "1024^2") as an integer."""
    if "^" in text:
        base, _, power = text.partition("^")
        return int(base) ** int(power)
    return int(text)


def find_group(path, n, aspect, sampling=None):
    """The one group of a file with that N and `Aspect ratio` text (and sampling method)."""
    hits = [g for g in read_groups(path)
            if n_value(g["tags"].get("N", "0")) == n and g["tags"].get("Aspect ratio") == aspect
            and (sampling is None or g["tags"].get("Sampling method") == sampling)]
    if len(hits) != 1:
        raise LookupError(f"{path}: {len(hits)} groups with N = {n}, aspect ratio {aspect}"
                          + (f", sampling {sampling}" if sampling else ""))
    group = hits[0]
    if group["tags"].get("X unit") != "packing fraction" \
            or group["tags"].get("Y unit") != "beta P (2 sigma)^2":
        raise ValueError(f"{path}: N = {n} {aspect}: units {group['tags']}")
    return group


if __name__ == "__main__":
    for p in sys.argv[1:] or [os.path.join(DATA, "ThisWork.csv")]:
        for g in read_groups(p):
            t = g["tags"]
            print(f"{os.path.basename(p)}: {t.get('Sampling method')}, N = {t.get('N')}, "
                  f"{t.get('Aspect ratio')}, {len(g['points'])} points "
                  f"({g['points'][0][0]} to {g['points'][-1][0]})")
