"""Every command printed in README.md and docs/ runs as printed (issue 22).

The commands are collected from the markdown (``doc_examples.printed_commands``): every
``gearrotor ...`` line of a fenced block and every inline code span that is a whole command;
usage lines (placeholders such as MODEL, brackets, alternatives) are synopses. Nothing is
listed by hand, so a command added to a doc is tested without touching this file.

* **Every command parses and its inputs load** (default suite, about a second each): the
  options and their values through the command line's own parser, the model file with its
  ``--set`` overrides, the bearing and study files it names.
* **Every synopsis names options its command has.**
* **Every command runs as printed** in a copy of ``examples/`` (a temporary folder is the
  working directory, so ``out/...`` is written there): exit status 0, or the status the doc
  states next to the command ("(exit status 3)"); the output printed under a ``$ gearrotor``
  prompt is the output. Commands that need a file an earlier command of the same doc writes
  (``transient-plot out/nominal.nc``, ``study report``) run that command first. The quick ones
  run in the default suite; the long ones (transients, studies, reports, sweeps) are marked
  slow, with the time each took on the shared 2-core test machine in FAST below.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest
import typer.main

from doc_examples import ENV, ROOT, PrintedCommand, printed_commands, run_gearrotor
from gearrotor.cli import app

COMMANDS, SYNOPSES = printed_commands()
GROUP = typer.main.get_command(app)

# Commands that run in the default suite: cheap on every model (measured single-threaded on
# the loaded 2-core machine: bearing 3-16 s, modal of the 2-shaft flagship without figures 3 s,
# static 5-10 s, torsional modes/campbell/response 3-6 s, an input error under a second).
# Everything else (transient 10-60 s, study run 3-11 min, report 40 s, figures, sweeps of
# hundreds of speeds, the API audit) is slow.
FAST_KINDS = {
    ("bearing",),
    ("static",),
    ("torsional", "modes"),
    ("torsional", "campbell"),
    ("mesh",),
}


def kind(cmd: PrintedCommand) -> tuple[str, ...]:
    return cmd.argv[:2] if cmd.argv[0] in ("study", "torsional") else cmd.argv[:1]


def expected_status(cmd: PrintedCommand) -> int:
    if cmd.output:  # an error shown under a prompt
        return 2 if cmd.output[0].startswith("error: ") else 0
    m = re.search(r"exit status (\d+)", cmd.comment)
    return int(m.group(1)) if m else 0


def depends_on(cmd: PrintedCommand) -> list[PrintedCommand]:
    """The earlier commands of the same doc that write a file ``cmd`` reads."""
    same = [c for c in COMMANDS if c.doc == cmd.doc]
    earlier = same[: same.index(cmd)]
    needs = [a for a in cmd.argv[1:] if not a.startswith("-") and not a.startswith("examples/")]
    out = []
    for c in earlier:
        writes = {c.argv[k + 1] for k, a in enumerate(c.argv[:-1]) if a in ("--output", "-o")}
        if any(n in writes for n in needs):
            out.append(c)
        elif (
            cmd.argv[0] == "study"
            and cmd.argv[1] != "run"
            and c.argv[:2] == ("study", "run")
            and c.argv[2] == cmd.argv[2]
            and not out
        ):
            out.append(c)
    return out


def folders_made_earlier(cmd: PrintedCommand) -> set[str]:
    """The folders of ``cmd``'s output files that an earlier command of its doc creates (a
    plot folder, another output's folder): a reader following the doc has them; with
    ``pytest -n`` that earlier command may have run on another worker."""
    same = [c for c in COMMANDS if c.doc == cmd.doc]
    outputs = [cmd.argv[k + 1] for k, a in enumerate(cmd.argv[:-1]) if a in ("--output", "-o")]
    wanted = {str(Path(o).parent) for o in outputs} - {"."}
    made = set()
    for c in same[: same.index(cmd)]:
        for k, a in enumerate(c.argv[:-1]):
            target = c.argv[k + 1]
            if a == "--plot":
                made |= {target, str(Path(target).parent)}
            elif a in ("--output", "-o"):
                made.add(str(Path(target).parent))
    return wanted & made


def is_fast(cmd: PrintedCommand) -> bool:
    if any(not is_fast(d) for d in depends_on(cmd)):
        return False
    if cmd.output or expected_status(cmd) == 2:
        return True
    if "--plot" in cmd.argv:
        return False
    if kind(cmd) == ("modal",):
        return "steam_turbine" not in cmd.argv[1] and "compressor" not in cmd.argv[1]
    return kind(cmd) in FAST_KINDS


def _ids(cmds):
    seen: dict[str, int] = {}
    out = []
    for c in cmds:
        seen[c.id] = seen.get(c.id, 0) + 1
        out.append(c.id if seen[c.id] == 1 else f"{c.id}#{seen[c.id]}")
    return out


def _resolve(argv: tuple[str, ...]):
    """(click command, its arguments) of ``gearrotor ARGV``."""
    cmd, args = GROUP, list(argv)
    while hasattr(cmd, "commands") and args and args[0] in cmd.commands:
        cmd, args = cmd.commands[args[0]], args[1:]
    return cmd, args


def test_docs_print_commands():
    docs = {c.doc for c in COMMANDS}
    assert "README.md" in docs and "docs/audit.md" in docs
    assert len(COMMANDS) > 60 and len(SYNOPSES) > 20
    kinds = {kind(c) for c in COMMANDS}
    for k in ("modal", "campbell", "unbalance", "static", "transient", "report", "ucs"):
        assert (k,) in kinds, k
    assert ("stability",) in kinds and ("floquet",) in kinds and ("study", "run") in kinds


def test_readme_table_lists_every_command():
    """The README's table of commands has a row for every command ``gearrotor --help`` lists."""
    readme = (ROOT / "README.md").read_text()
    rows = set(re.findall(r"^\| `gearrotor ([a-z-]+)", readme, flags=re.M))
    assert set(GROUP.commands) <= rows, set(GROUP.commands) - rows


# --------------------------------------------------------------------------------------------
# default suite: every command parses and loads its inputs
# --------------------------------------------------------------------------------------------


def make_workspace(path: Path) -> Path:
    """A copy of examples/ in ``path`` (and tests/ linked), with the README's bad.toml (the
    flagship with its gear on node 99)."""
    shutil.copytree(ROOT / "examples", path / "examples")
    (path / "tests").symlink_to(ROOT / "tests")  # docs/interop.md reads tests/data/ross
    text = (ROOT / "examples" / "unity_gearbox.toml").read_text()
    bad = text.replace(
        'gear = { shaft = "shaft1", node = 10,', 'gear = { shaft = "shaft1", node = 99,'
    )
    assert bad != text
    (path / "bad.toml").write_text(bad)
    return path


@pytest.fixture
def workspace(tmp_path) -> Path:
    return make_workspace(tmp_path)


@pytest.mark.parametrize("cmd", COMMANDS, ids=_ids(COMMANDS))
def test_printed_command_parses_and_loads(cmd, workspace, monkeypatch):
    from gearrotor.inputs import read_toml
    from gearrotor.io import load_model, parse_overrides

    command, args = _resolve(cmd.argv)
    assert not hasattr(command, "commands"), f"{cmd.shell}: not a command"
    # the command line's own parser: option names, values (speeds with units, counts, ...)
    command.make_context(" ".join(cmd.argv[:1]), list(args))
    monkeypatch.chdir(workspace)
    files = [a for a in args if a.endswith(".toml") and not a.startswith("-")]
    if not files:
        return
    sets = [args[k + 1] for k, a in enumerate(args[:-1]) if a == "--set"]
    if not Path(files[0]).exists():  # written by an earlier command of the doc
        assert depends_on(cmd), cmd.shell
        return
    data = read_toml(Path(files[0]), "input")
    if cmd.argv[0] == "study":
        from gearrotor.studies import load_study

        load_study(files[0])
    elif "shafts" not in data:  # a bearing, seal, gear-pair or ROSS file: read above
        assert cmd.argv[0] in ("bearing", "seal", "mesh", "import-ross"), cmd.shell
        if cmd.argv[0] == "mesh":
            from gearrotor.gears import load_gear_pair

            load_gear_pair(files[0])
    elif expected_status(cmd) == 2:
        with pytest.raises(ValueError) as err:
            load_model(files[0], parse_overrides(sets))
        assert cmd.output == (f"error: {err.value}",)
    else:
        load_model(files[0], parse_overrides(sets))


SYNOPSIS_OPTIONS = [
    (s, opt)
    for s in SYNOPSES
    for opt in re.findall(r"(?<![\w-])--[a-z][\w-]*\w(?![\w.-])", " ".join(s.argv))
]


@pytest.mark.parametrize(
    "syn,option",
    SYNOPSIS_OPTIONS,
    ids=[f"{s.doc}:{s.line}:{o}" for s, o in SYNOPSIS_OPTIONS],
)
def test_synopses_name_real_options(syn, option):
    words = [a for a in syn.argv if not a.startswith(("-", "[")) and "|" not in a]
    command, _ = _resolve(tuple(words))
    if hasattr(command, "commands"):  # `gearrotor torsional modes|campbell|...`: any of them
        subs = list(command.commands.values())
    else:
        subs = [command]
    names = {o for c in subs for p in c.params for o in (*p.opts, *p.secondary_opts)}
    names.add("--help")
    assert option in names, (syn.doc, syn.line, syn.shell)


# --------------------------------------------------------------------------------------------
# every command runs as printed
# --------------------------------------------------------------------------------------------

_DONE: dict[tuple[str, str], Path] = {}


def _run(cmd: PrintedCommand, where: Path) -> subprocess.CompletedProcess:
    """``cmd`` run in ``where``, with the folders the doc's earlier commands make there (a
    reader following the doc has them, whichever worker ran those commands)."""
    for folder in folders_made_earlier(cmd):
        (where / folder).mkdir(parents=True, exist_ok=True)
    env = dict(ENV, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), ENV.get("PYTHONPATH", "")]))
    return run_gearrotor(cmd.argv, where, env, timeout=1800)


@pytest.fixture(scope="module")
def doc_workspaces(tmp_path_factory):
    """One working folder per doc (its commands share the files they write)."""
    spaces: dict[str, Path] = {}

    def get(doc: str) -> Path:
        if doc not in spaces:
            spaces[doc] = make_workspace(tmp_path_factory.mktemp(re.sub(r"\W", "_", doc)))
        return spaces[doc]

    return get


def _chains() -> dict[int, str]:
    """Commands linked by the files they write and read, one name per chain (the first
    command's): a chain runs on one pytest-xdist worker (``--dist loadgroup``), where the
    files its first commands wrote are already there (``_DONE``) instead of being written
    again by the worker that runs a later command."""
    root = list(range(len(COMMANDS)))

    def find(i: int) -> int:
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    def join(i: int, j: int) -> None:
        a, b = sorted((find(i), find(j)))
        root[b] = a

    index = {id(c): k for k, c in enumerate(COMMANDS)}
    linked = set()
    for k, cmd in enumerate(COMMANDS):
        for dep in depends_on(cmd):
            join(k, index[id(dep)])
            linked |= {k, index[id(dep)]}
    # the same command in the chains of several docs (`study run` of the seed study in README,
    # docs/seed_study.md, docs/studies.md): one chain and one folder, so that the first run
    # computes and the others find it done, as a reader who follows both docs does
    first: dict[tuple[str, ...], int] = {}
    for k in sorted(linked):
        join(k, first.setdefault(COMMANDS[k].argv, k))
    # and another scheduler's `study run` of that study (docs/studies.md prints them one after
    # the other: a reader who runs both finds the study done by the first)
    for k, cmd in enumerate(COMMANDS):
        plain = cmd.argv[:3]
        if cmd.argv[:2] == ("study", "run") and plain != cmd.argv and plain in first:
            join(k, first[plain])
    sizes: dict[int, int] = {}
    for k in range(len(COMMANDS)):
        sizes[find(k)] = sizes.get(find(k), 0) + 1
    return {
        k: f"doc-chain:{COMMANDS[find(k)].doc}:{COMMANDS[find(k)].line}"
        for k in range(len(COMMANDS))
        if sizes[find(k)] > 1
    }


CHAINS = _chains()


def _params():
    """One test per printed command; a command printed again outside any chain (the same
    report in README and docs/performance.md) runs once, under its first place."""
    out = []
    seen: set[tuple[str, ...]] = set()
    for k, (cmd, id_) in enumerate(zip(COMMANDS, _ids(COMMANDS), strict=True)):
        marks = [] if is_fast(cmd) else [pytest.mark.slow]
        if k in CHAINS:
            marks.append(pytest.mark.xdist_group(CHAINS[k]))
        elif cmd.argv in seen:
            continue
        seen.add(cmd.argv)
        out.append(pytest.param(cmd, id=id_, marks=marks))
    return out


def _workspace_of(cmd: PrintedCommand) -> str:
    """The folder a command runs in: its chain's, else its doc's."""
    k = next(k for k, c in enumerate(COMMANDS) if c is cmd)
    return CHAINS.get(k, cmd.doc)


@pytest.mark.parametrize("cmd", _params())
def test_printed_command_runs(cmd, doc_workspaces):
    where = doc_workspaces(_workspace_of(cmd))
    for dep in depends_on(cmd):
        if (dep.doc, dep.shell) not in _DONE:
            p = _run(dep, where)
            assert p.returncode == expected_status(dep), (dep.shell, p.stderr[-2000:])
            _DONE[(dep.doc, dep.shell)] = where
    p = _run(cmd, where)
    status = expected_status(cmd)
    assert p.returncode == status, (cmd.shell, p.stderr[-3000:])
    _DONE[(cmd.doc, cmd.shell)] = where
    if cmd.output:
        shown = (p.stdout + p.stderr).strip().splitlines()
        assert shown == list(cmd.output), (shown, cmd.output)
