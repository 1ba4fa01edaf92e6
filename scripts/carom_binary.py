"""The carom binary a validation script runs: --carom as given, or relative to the project."""
import os
import sys

PROJECT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def carom_binary(given):
    """The absolute path of `given` (relative paths that do not exist here are taken from the
    project's folder); exits with a message when it is not an executable."""
    carom = given
    if not os.path.isabs(carom) and not os.path.exists(carom):
        carom = os.path.join(PROJECT, carom)
    carom = os.path.abspath(carom)
    if not os.access(carom, os.X_OK):
        sys.exit(f"no carom binary at {carom}: build it or pass --carom")
    return carom
