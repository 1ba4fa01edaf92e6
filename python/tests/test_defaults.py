"""Every default the Python API shows is the library's, the same the command line's help shows:
one number in one place (carom._carom.defaults), so that Python and the command line cannot
drift apart."""

import inspect
import re

import pytest

import carom


def help_defaults(cli, command):
    """The defaults `carom COMMAND --help` prints, as {option: text}."""
    text = cli(command, "--help")
    return dict(re.findall(r"^\s+--([\w-]+) [A-Z:]+=(\S+)", text, re.MULTILINE))


# Python function, its parameter, the command and its option.
SAME = [
    (carom.read, "tc", "run", "tc"),
    (carom.read, "restitution", "run", "restitution"),
    (carom.read, "seed", "run", "seed"),
    (carom.init, "kT", "init", "kT"),
    (carom.init, "seed", "init", "seed"),
    (carom.init, "aspect", "init", "aspect"),
    (carom.init, "polydispersity", "init", "polydispersity"),
    (carom.compress, "rate", "compress", "rate"),
    (carom.compress, "kT", "compress", "kT"),
    (carom.compress, "jam_pressure", "compress", "jam-pressure"),
]


@pytest.mark.parametrize("function,parameter,command,option", SAME,
                         ids=[f"{f.__name__}-{p}" for f, p, _, _ in SAME])
def test_python_defaults_are_the_command_lines(cli, function, parameter, command, option):
    shown = inspect.signature(function).parameters[parameter].default
    assert float(shown) == float(help_defaults(cli, command)[option])


def test_every_numeric_default_comes_from_the_library():
    # The package's source holds no number as a default: each is read from carom._carom.defaults.
    for function in (carom.read, carom.init, carom.compress, carom.Simulation.__init__):
        for name, parameter in inspect.signature(function).parameters.items():
            default = parameter.default
            if isinstance(default, (int, float)) and not isinstance(default, bool):
                assert any(default == value and type(default) is type(value)
                           for value in carom._carom.defaults.values()), (function, name)
    source = inspect.getsource(carom)
    for match in re.finditer(r"def (\w+)\(([^)]*)\)", source):
        public = not match.group(1).startswith("_") or match.group(1) == "__init__"
        if public:
            assert not re.search(r"=\s*-?\d", match.group(2)), match.group(0)
