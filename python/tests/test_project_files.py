"""The files that say what carom is and how to cite it agree with the build: CITATION.cff names
the version CMake builds (and the module reports) and the licence in LICENSE."""
import os
import pathlib
import re

import carom

SOURCE = pathlib.Path(os.environ.get("CAROM_SOURCE_DIR", pathlib.Path(__file__).parents[2]))


def cff_value(key):
    match = re.search(rf"^{key}:\s*(.+)$", (SOURCE / "CITATION.cff").read_text(), re.M)
    assert match, f"CITATION.cff has no {key}"
    return match.group(1).strip().strip('"')


def test_the_citation_names_the_version_built():
    cmake = re.search(r"project\(carom VERSION (\S+)", (SOURCE / "CMakeLists.txt").read_text())
    assert cff_value("version") == cmake.group(1) == carom.__version__


def test_the_citation_names_the_licence_of_license():
    assert cff_value("license") == "BSD-3-Clause"
    assert (SOURCE / "LICENSE").read_text().startswith("BSD 3-Clause License\n")
    assert re.fullmatch(r"\d{4}-\d{2}-\d{2}", cff_value("date-released"))
