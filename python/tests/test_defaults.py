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


def test_the_choices_are_the_librarys():
    # The names Python accepts are the library's tables, the default first.
    names = carom._carom.names
    assert names["rule"][0] == "swap" and set(names["rule"]) == {"swap", "elastic"}
    assert names["placement"] == ["auto", "random", "lattice"]
    for rule in names["rule"]:
        assert carom.init(n=10, phi=0.1, rule=rule).rule == rule
    for placement in names["placement"]:
        carom.init(n=10, phi=0.1, placement=placement)


def test_signatures_show_the_requests_keywords():
    # read, init and run take the keywords of the library's requests, shown with its defaults.
    for function, spec in ((carom.read, carom._carom.StartSpec),
                           (carom.init, carom._carom.InitSpec),
                           (carom.Simulation.run, carom._carom.RunSpec)):
        parameters = inspect.signature(function).parameters
        for keyword, default in spec.keywords().items():
            assert keyword in parameters, (function, keyword)
            if parameters[keyword].default is not inspect.Parameter.empty:
                assert parameters[keyword].default == default, (function, keyword)
    assert inspect.signature(carom.init).parameters["dim"].default == carom._carom.defaults["dim"]


def test_no_module_of_the_package_holds_a_numeric_default():
    import pkgutil
    for module in pkgutil.iter_modules(carom.__path__):
        if module.name.startswith("_carom"):
            continue
        source = inspect.getsource(__import__(f"carom.{module.name}", fromlist=["_"]))
        for match in re.finditer(r"def (\w+)\(([^)]*)\)", source):
            public = not match.group(1).startswith("_") or match.group(1) == "__init__"
            if public:
                assert not re.search(r"=\s*-?\d", match.group(2)), (module.name, match.group(0))
