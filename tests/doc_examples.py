"""Shared pieces of the worked-example tests: run the ``gearrotor ...`` commands of a doc."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# single-threaded BLAS: on a loaded 2-core machine a threaded dense eigensolve can be 50x slower
ENV = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")


# --------------------------------------------------------------------------------------------
# `gearrotor ...` as a process of its own, without paying the interpreter's imports each time
# --------------------------------------------------------------------------------------------

#: What a command imports before it starts (1.3-1.8 s of CPU on the test machine, most of a
#: quick command's time): imported once in a fork server, which forks one process per command.
#: Every module of the package, not only the command line's: the analyses a command imports
#: once it runs (the transient kernels, the audit, xarray, SciPy's optimisers, ...) cost the
#: forked commands ~170 s of CPU in a ~1,100-s suite run (py-spy over the whole suite) when
#: only the command line was preloaded; the server imports them once per test worker (~2 s).
#: Also what the commands import only when they run (not at the package's import): SciPy's
#: signal package (the transient summary's peak finder, ~0.7 s), pyplot, and dask and
#: distributed, which xarray imports on every NetCDF write and duck-array check (~25 s of the
#: forked commands' CPU in a suite run with only the package preloaded); and the command
#: line's click command, built once (:mod:`cli_cache`). Not CoolProp (~2 s to import, ~3 s
#: over the few seal commands that use it).
_PRELOAD = [
    "numpy",
    "scipy.linalg",
    "scipy.sparse",
    "scipy.signal",
    "scipy.optimize",
    "pint",
    "matplotlib",
    "matplotlib.pyplot",
    "dask.array",
    "distributed",
    "h5netcdf",
    "gearrotor.cli",
    "cli_cache",
]
_CONTEXT = None


def _package_modules() -> list[str]:
    """The names of gearrotor's modules, from its source files (nothing imported here)."""
    src = ROOT / "src"
    names = []
    for path in sorted((src / "gearrotor").rglob("*.py")):
        parts = path.relative_to(src).with_suffix("").parts
        if parts[-1] == "__main__":
            continue
        names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def _context():
    global _CONTEXT
    if _CONTEXT is None:
        import multiprocessing

        _CONTEXT = multiprocessing.get_context("forkserver")
        _CONTEXT.set_forkserver_preload(_PRELOAD + _package_modules())
    return _CONTEXT


def _command_process(argv, cwd, env, out_path, err_path) -> None:  # pragma: no cover (child)
    """In the forked process: what ``python -m gearrotor ARGV`` does in ``cwd`` with ``env``,
    stdout and stderr to files; the process exits with the command's status."""
    import sys
    import traceback

    os.chdir(cwd)
    os.environ.clear()
    os.environ.update(env)
    for fd, path in ((1, out_path), (2, err_path)):
        f = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        os.dup2(f, fd)
        os.close(f)
    sys.stdout = open(1, "w", encoding="utf-8", closefd=False)  # noqa: SIM115
    sys.stderr = open(2, "w", encoding="utf-8", closefd=False)  # noqa: SIM115
    sys.stdin = open(os.devnull)  # noqa: SIM115
    sys.argv = ["gearrotor", *argv]
    status = 0
    try:
        from threadpoolctl import threadpool_limits

        if env.get("OPENBLAS_NUM_THREADS"):
            threadpool_limits(int(env["OPENBLAS_NUM_THREADS"]))
        from gearrotor.cli import main

        main()
    except SystemExit as exc:
        code = exc.code
        if code is None:
            status = 0
        elif isinstance(code, int):
            status = code
        else:
            print(code, file=sys.stderr)
            status = 1
    except BaseException:
        traceback.print_exc()
        status = 1
    import atexit

    atexit._run_exitfuncs()  # as the interpreter does at exit (os._exit skips it)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)


def run_gearrotor(argv, cwd, env=None, timeout: float = 1800) -> subprocess.CompletedProcess:
    """``python -m gearrotor ARGV`` in ``cwd`` (a process of its own: its exit status, signal
    handlers, output streams and current folder are its own, as in a shell), forked from a
    server that has imported what every command imports."""
    import tempfile

    env = dict(ENV if env is None else env)
    with tempfile.TemporaryDirectory(prefix="gearrotor-cmd-") as tmp:
        out_path, err_path = os.path.join(tmp, "out"), os.path.join(tmp, "err")
        proc = _context().Process(
            target=_command_process, args=(list(argv), str(cwd), env, out_path, err_path)
        )
        proc.start()
        proc.join(timeout)
        if proc.is_alive():
            proc.kill()
            proc.join()
            raise subprocess.TimeoutExpired(["gearrotor", *argv], timeout)
        with open(out_path, encoding="utf-8", errors="replace") as fh:
            stdout = fh.read()
        with open(err_path, encoding="utf-8", errors="replace") as fh:
            stderr = fh.read()
    return subprocess.CompletedProcess(["gearrotor", *argv], proc.exitcode, stdout, stderr)


def run(args: list[str], timeout: float = 600, status: int = 0) -> subprocess.CompletedProcess:
    """Run a command in the repository root; assert its exit status. ``[sys.executable, "-m",
    "gearrotor", ...]`` runs through :func:`run_gearrotor`."""
    import sys

    if list(args[:3]) == [sys.executable, "-m", "gearrotor"]:
        out = run_gearrotor(args[3:], ROOT, ENV, timeout)
    else:
        out = subprocess.run(
            args, cwd=ROOT, env=ENV, capture_output=True, text=True, timeout=timeout
        )
    assert out.returncode == status, f"{args}\n{out.stderr[-3000:]}"
    return out


def doc_commands(doc: Path) -> list[tuple[list[str], str]]:
    """(argv after ``gearrotor``, trailing comment) of the doc's bash blocks, continuation
    lines joined."""
    cmds = []
    for block in re.findall(r"```bash\n(.*?)```", doc.read_text(), flags=re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        for line in joined.splitlines():
            line = line.strip()
            if not line.startswith("gearrotor "):
                continue
            cmd, _, comment = line.partition("#")
            cmds.append((shlex.split(cmd)[1:], comment.strip()))
    return cmds


def find_run(runs, kind: str, *words: str, without: tuple[str, ...] = ()) -> dict:
    """The one result of a ``kind`` command whose arguments contain all ``words`` and none of
    ``without``."""
    hits = [
        r
        for c, r in runs
        if c[0] == kind
        and all(any(w in a for a in c) for w in words)
        and not any(any(w in a for a in c) for w in without)
    ]
    assert len(hits) == 1, (kind, words, [c for c, _ in runs])
    return hits[0]


# --------------------------------------------------------------------------------------------
# Every command printed in README.md and docs/: collected from the markdown, not listed by hand
# --------------------------------------------------------------------------------------------

DOCS = (ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md")))

# a synopsis names its arguments by placeholders (MODEL, DIR, FILE.nc, RPM) or brackets
_PLACEHOLDER = re.compile(r"^(--[\w-]+=)?[A-Z][A-Z0-9_]*[A-Z](\.[a-z]+)?,?$")


@dataclass(frozen=True)
class PrintedCommand:
    """One ``gearrotor ...`` command as printed in a doc."""

    doc: str  # path relative to the repository root
    line: int  # 1-based line of the command's first line
    argv: tuple[str, ...]  # the arguments after ``gearrotor``
    comment: str  # the trailing ``# ...`` comment, if any
    output: tuple[str, ...] = ()  # printed output that follows a ``$ gearrotor`` prompt line

    @property
    def id(self) -> str:
        return f"{self.doc}:{self.line}:{' '.join(self.argv[:2])}"

    @property
    def shell(self) -> str:
        return "gearrotor " + shlex.join(self.argv)


def raw_tokens(raw: str) -> list[str]:
    """The unquoted words of a shell line (quoted parts removed)."""
    return re.sub(r"'[^']*'|\"[^\"]*\"", "", raw.partition(" #")[0]).split()


def _is_synopsis(argv: list[str], raw: str) -> bool:
    """True for a usage line (``gearrotor modal MODEL [--speed RPM]``), a reference to a
    command by name (``gearrotor stability``) or anything else that names no input file."""
    if any(_PLACEHOLDER.match(a) for a in argv):
        return True
    # a placeholder inside a token (tcp://HOST:8786), outside quotes
    if any(re.search(r"(?<![A-Za-z])[A-Z]{3,}(?![A-Za-z])", a) for a in raw_tokens(raw)):
        return True
    unquoted = re.sub(r"'[^']*'|\"[^\"]*\"", "", raw)
    if re.search(r"(^|\s)\[", unquoted) or "|" in unquoted or "..." in unquoted:
        return True
    return not any(a.endswith((".toml", ".nc", ".json")) for a in argv)


def _split_line(line: str) -> tuple[list[str], str] | None:
    """(argv after ``gearrotor``, comment) of one shell line, or None if no gearrotor command.
    ``pip install ... && gearrotor ...`` keeps the gearrotor part."""
    line = line.strip().removeprefix("$ ").strip()
    for part in re.split(r"\s*&&\s*", line):
        if part.startswith("gearrotor "):
            lexer = shlex.shlex(part, posix=True, punctuation_chars=False)
            lexer.whitespace_split = True
            lexer.commenters = "#"
            argv = list(lexer)
            comment = part.partition(" #")[2].strip() if " #" in part else ""
            return argv[1:], comment
    return None


def _expand_loops(block: str) -> str:
    """``for v in a b c; do BODY done`` -> BODY once per value (the seed study's loop)."""

    def expand(m: re.Match) -> str:
        var, values, body = m.group(1), m.group(2).split(), m.group(3).strip()
        return "\n".join(body.replace("$" + var, v) for v in values)

    return re.sub(r"for (\w+) in ([^;\n]+); do\s*(.*?)\s*done", expand, block, flags=re.S)


def printed_commands(docs=DOCS) -> tuple[list[PrintedCommand], list[PrintedCommand]]:
    """(commands, synopses) printed in ``docs``: every ``gearrotor ...`` line of a fenced block
    (any language; continuation lines joined, ``$ `` prompts dropped, the output printed under a
    prompt kept, shell ``for`` loops expanded) and every inline code span that starts with
    ``gearrotor ``. Synopses (placeholders, brackets, bare command names) are returned apart."""
    commands, synopses = [], []
    for doc in docs:
        text = doc.read_text()
        rel = str(doc.relative_to(ROOT))
        fenced = []
        for m in re.finditer(r"^```[^\n]*\n(.*?)^```", text, flags=re.S | re.M):
            fenced.append(m.span())
            first = text.count("\n", 0, m.start(1)) + 1
            body = _expand_loops(re.sub(r"\\\n\s*", " ", m.group(1)))
            lines = body.splitlines()
            cursor = 0
            for k, line in enumerate(lines):
                got = _split_line(line)
                if got is None:
                    continue
                argv, comment = got
                output: tuple[str, ...] = ()
                if line.lstrip().startswith("$ "):
                    rest = []
                    for nxt in lines[k + 1 :]:
                        if nxt.lstrip().startswith("$ "):
                            break
                        rest.append(nxt)
                    output = tuple(rest)
                # line number of the command in the doc (joined continuations shift it)
                at = m.group(1).find(line.strip()[:20], cursor)
                cursor = max(at + 1, cursor)
                lineno = first + m.group(1).count("\n", 0, at) if at >= 0 else first
                cmd = PrintedCommand(rel, lineno, tuple(argv), comment, output)
                (synopses if _is_synopsis(argv, line) else commands).append(cmd)
        for m in re.finditer(r"`(gearrotor [^`]+)`", text):
            if any(a <= m.start() < b for a, b in fenced):
                continue
            raw = " ".join(m.group(1).split())
            got = _split_line(raw)
            if got is None:
                continue
            argv, comment = got
            cmd = PrintedCommand(rel, text.count("\n", 0, m.start()) + 1, tuple(argv), comment)
            (synopses if _is_synopsis(argv, raw) else commands).append(cmd)
    return commands, synopses
