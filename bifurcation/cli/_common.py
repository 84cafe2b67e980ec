"""Shared CLI plumbing: one-line errors with exit status 2, JSON output, shared options."""

from __future__ import annotations

import errno
import io
import json
import math
import os
import signal
import sys
import threading
from contextlib import contextmanager
from pathlib import Path

import click

from ..errors import InputError, Terminated, stop

__all__ = ["Group", "as_typed", "quiet_heyoka", "check_out_dir", "check_outside_stores", "check_replace", "check_writable_dir", "echo_json", "examples", "fail", "format_value", "native_stdout_to_stderr", "number"]


def fail(message: str) -> None:
    """Print one line to stderr and exit with status 2 (bad input), without a traceback."""
    click.echo(f"bifurcation: error: {message}", err=True)
    sys.exit(2)


def _repeated_option(command: click.Command, args: list[str]) -> str | None:
    """The first option of ``command`` that takes one value but appears twice in ``args``, if any."""
    single, flags = {}, {}
    for param in command.params:
        if isinstance(param, click.Option) and not param.multiple and not param.count:
            for opt in param.opts:
                single[opt] = param.name
                flags[opt] = param.is_flag
    seen: dict[str, str] = {}
    for i, arg in enumerate(args):
        if arg == "--":
            break
        opt, eq, value = arg.partition("=")
        name = single.get(opt)
        if name is None:
            continue
        if flags.get(opt):
            if name in seen:
                return f"{opt} is given twice: give it once"
            seen[name] = opt
            continue
        if not eq:
            value = args[i + 1] if i + 1 < len(args) else ""
        if name in seen:
            return f"{opt} is given twice ({seen[name]} and {value}): give it once"
        seen[name] = value
    return None


def _given(command: click.Command, args: list[str], prefix: str = ""):
    """The values ``args`` give to ``command``'s options and arguments, as click will read them: (the command
    they belong to, its group prefix, the name as typed, the click parameter, the value or None if missing);
    a group hands on to its subcommand (`study chain WORKFLOW`). Flags and unknown options give nothing."""
    if isinstance(command, click.Group):
        sub = command.commands.get(args[0]) if args else None
        if sub is not None:
            yield from _given(sub, args[1:], f"{prefix}{command.name} ")
        return
    takes = {opt: p for p in command.params if isinstance(p, click.Option) and not p.is_flag for opt in p.opts}
    positional = [p for p in command.params if isinstance(p, click.Argument)]
    i, position = 0, 0
    while i < len(args):
        arg = args[i]
        opt, eq, value = arg.partition("=")
        if opt in takes and eq:
            yield command, prefix, opt, takes[opt], value
        elif arg in takes:
            i += 1
            yield command, prefix, arg, takes[arg], args[i] if i < len(args) else None
        elif not (arg.startswith("-") and arg.strip("-")) and positional:
            param = positional[min(position, len(positional) - 1)]
            position += 1
            yield command, prefix, param.human_readable_name, param, arg
        i += 1


def _empty_value(command: click.Command, args: list[str]) -> str | None:
    """An empty (or blank) value given to an option or argument of ``command``, named as typed with '' (a
    path made of it reads as '.', the working directory: `export --store ''` said --store='.')."""
    for leaf, prefix, name, _, value in _given(command, args):
        if value is not None and not value.strip():
            return f"{name}={value!r}: is empty; give a value (`bifurcation {prefix}{leaf.name} --help` says which)"
    return None


#: Parameters that name a file or directory: their values are checked for names the system cannot take.
_PATHS = ("store", "stores", "out", "workflow", "scheduler")


def _bad_path(command: click.Command, args: list[str]) -> str | None:
    """A path given to --store, --out, --scheduler or WORKFLOW that no command could use: a name longer than the system
    takes (a traceback-free exit 1 after the work, or a half-made parent directory, before) or a symbolic
    link that loops or points nowhere (``Path.exists`` calls it missing, so outputs failed at the end with
    'File exists')."""
    for _, _, name, param, value in _given(command, args):
        if param.name not in _PATHS or not value:
            continue
        shown = value if len(value) <= 80 else value[:60] + "…" + value[-15:]
        try:   # bytes that are not UTF-8 reach Python as surrogates: netCDF4 raised UnicodeEncodeError on them
            value.encode("utf-8")
        except UnicodeEncodeError as exc:
            return (f"{name}={shown!r}: has a byte that is not UTF-8 ({value[exc.start]!r} at {exc.start + 1}); "
                    "give a path in UTF-8")
        raw = os.fsencode(value)
        longest = max(raw.split(b"/"), key=len)
        if len(longest) > 255 or len(raw) > 4095:
            what = (f"has a name of {len(longest)} bytes (the limit is 255)" if len(longest) > 255 else
                    f"is {len(raw)} bytes long (the limit is 4095)")
            return f"{name}={shown!r}: {what}; give a shorter path"
        try:
            os.stat(value)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                return (f"{name}={shown!r}: is a symbolic link that loops (or a chain of more than 40); "
                        "remove or fix the link, or give another path")
            if exc.errno == errno.ENOENT and os.path.islink(value):   # mkdir does not follow it: exit 1 after the work
                return (f"{name}={shown!r}: is a symbolic link to {os.readlink(value)!r}, which does not exist; "
                        "create that, or give another path")
    return None


def _stdout_closed() -> bool:
    """Whether standard output is a pipe whose reader has gone (poll reports POLLERR on it)."""
    import select

    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLOUT)
        return any(event & select.POLLERR for _, event in poller.poll(0))
    except (OSError, ValueError, AttributeError):   # no real fd (a test runner's buffer)
        return False


def _bad_environment() -> str | None:
    """An environment variable a library reads at import, checked before the command: NUMBA_NUM_THREADS=0 was
    numba's ValueError traceback from the compiled chain engine, after the command had begun (walk 6)."""
    text = os.environ.get("NUMBA_NUM_THREADS")
    if text is not None and not (text.strip().isdigit() and int(text) > 0):
        return (f"NUMBA_NUM_THREADS={text!r}: is not a positive number of threads (numba reads it); unset it, or "
                "give e.g. NUMBA_NUM_THREADS=2")
    return None


class Group(click.Group):
    """A command group whose usage and input errors are one line and exit with status 2.

    An option that takes one value and is given twice is refused (click would silently keep the last).
    Ctrl-C ends with status 130, SIGTERM and SIGHUP with 128 + the signal, and each says what is kept.
    """

    _command: click.Command | None = None

    def resolve_command(self, ctx, args):
        name, command, rest = super().resolve_command(ctx, args)
        self._command = command
        if command is not None:
            problem = (_repeated_option(command, rest) or _empty_value(command, rest) or _bad_path(command, rest)
                       or _bad_environment())
            if problem:
                raise click.UsageError(problem)
        return name, command, rest

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except BrokenPipeError:
            if not _stdout_closed():   # another pipe (a worker's): not the reader's choice; an error
                raise
            # the reader closed our stdout (`bifurcation laws | head -1`): stop quietly with the status of a
            # Unix tool ended by SIGPIPE (128 + 13), no error line; the unwritten rest goes to /dev/null so
            # the flush at exit cannot fail again
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)
            sys.exit(141)

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        try:
            with _stop_on_signals():
                return super().main(args=args, prog_name=prog_name or "bifurcation",
                                    complete_var=complete_var, standalone_mode=False, **extra)
        except click.exceptions.Exit as exc:
            sys.exit(exc.exit_code)
        except (click.exceptions.Abort, KeyboardInterrupt):
            name = getattr(self._command, "name", None)
            click.echo(f"bifurcation: interrupted. {_KEPT.get(name, 'Nothing of this run was written.')}", err=True)
            sys.exit(130)
        except Terminated as exc:   # SIGTERM (a batch job's walltime), SIGHUP: the same clean stop as Ctrl-C
            name = getattr(self._command, "name", None)
            click.echo(f"bifurcation: terminated by {signal.Signals(exc.signum).name}. "
                       f"{_KEPT.get(name, 'Nothing of this run was written.')}", err=True)
            sys.exit(128 + exc.signum)
        except click.UsageError as exc:
            fail(" ".join(exc.format_message().split()))
        except InputError as exc:
            fail(" ".join(as_typed(exc, self._command).split()))
        except click.ClickException as exc:
            click.echo(f"bifurcation: error: {exc.format_message()}", err=True)
            sys.exit(exc.exit_code)
        except OSError as exc:   # disk full, permissions, a vanished file: the system's one line, no traceback
            where = f": {exc.filename}" if getattr(exc, "filename", None) else ""
            stores = getattr(self._command, "name", None) in ("submit", "reproduce", "verify")
            fix = ("; free some space (or choose another --store) and run the same command again: finished "
                   "tiles are kept" if exc.errno == errno.ENOSPC and stores else
                   "; free some space and run the same command again" if exc.errno == errno.ENOSPC else "")
            click.echo(f"bifurcation: error: {exc.strerror or exc}{where}{fix}", err=True)
            sys.exit(1)


#: Signals that stop a command cleanly: a batch scheduler's SIGTERM at the walltime (Slurm sends SIGKILL
#: after its grace period, KillWait), a closed terminal's SIGHUP.
_STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


def _raise_terminated(signum, frame):
    for other in _STOP_SIGNALS:   # one stop: a second signal must not interrupt the cleanup (lock release)
        signal.signal(other, signal.SIG_IGN)
    stop(signum)   # raises Terminated now, or once the tile being written is whole (errors.uninterrupted)


def _raise_interrupt(signum, frame):
    stop(signum)   # KeyboardInterrupt now, or once the tile being written is whole (a second Ctrl-C: the same)


@contextmanager
def _stop_on_signals():
    """SIGTERM and SIGHUP raise ``Terminated`` while a command runs (without a handler the process died
    at once and left its store's lock behind, which a submit from another node may not break). A signal
    that is ignored (``nohup``) stays ignored; off the main thread (signal handlers cannot be set there)
    nothing changes. The previous handlers are restored afterwards. Ctrl-C (SIGINT) still raises
    KeyboardInterrupt, but one inside a tile's write waits for its end too (when Python's own handler is
    in place: another one, a caller's, is left alone)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in (*_STOP_SIGNALS, signal.SIGINT)}
    try:
        for s, handler in previous.items():
            if s == signal.SIGINT:
                if handler is signal.default_int_handler:
                    signal.signal(s, _raise_interrupt)
            elif handler is not signal.SIG_IGN:
                signal.signal(s, _raise_terminated)
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)


#: What an interrupted command kept, by command (the submit's words were printed for every command: a
#: `continue` or `study chain` user was told to submit again and that tiles were kept, found at review).
_KEPT = {
    "submit": "A submit keeps every finished tile in its store: submit the same workflow again to resume.",
    "reproduce": "Every finished tile is kept in the paper's stores: run the same command again to resume.",
    "verify": "A repair keeps every tile it recomputed: run the same command again to finish it.",
    "continue": "continue writes its store and report only at the end, so this run left nothing new (an "
                "earlier output in --out is kept): run the same command again; it starts from the beginning.",
    "study": "A study writes its directory only at the end, so this run left nothing new: run the same "
             "command again; it starts from the beginning (`study chain --ell-scan-only` keeps each finished "
             "sweep in ell_scan.json and resumes from there).",
}


def as_typed(exc: InputError, command: click.Command | None) -> str:
    """``exc`` as one line naming the argument as the user typed it: an error about the parameter
    ``nu_f`` of the command that ran reads ``--nu-f=…``, about its argument ``workflow`` ``WORKFLOW=…``;
    other names (``grid.nu.values[0]``, a table key of a TOML file) are kept as they are."""
    argument = exc.argument
    for param in getattr(command, "params", ()):
        if argument in (param.name, (param.name or "").replace("_", "-")):
            if isinstance(param, click.Option):
                argument = max(param.opts, key=len)
            elif isinstance(param, click.Argument):
                argument = param.human_readable_name
            break
    return exc.line(argument)


def _clean(obj):
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    return obj


def examples(*commands: str) -> str:
    """A command's epilog: its examples, one ``$ bifurcation …`` line each, kept as written by click
    (``\\b``). tests/test_cli_examples.py runs every one of them."""
    return "Examples:\n\n\b\n" + "\n".join(f"  $ {c}" for c in commands)


def format_value(value) -> str:
    """A value for people: floats in their shortest exact form (``1e-09``, not
    ``1.0000000000000001e-09``; every digit printed is significant and the float reads back the
    same), a missing value as ``—``."""
    if value is None:
        return "—"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else "—" if math.isnan(value) else repr(value)
    return str(value)


def echo_json(obj) -> None:
    """Print ``obj`` as strict JSON (NaN and inf become null)."""
    click.echo(json.dumps(_clean(obj), indent=2, allow_nan=False))


def _not_a_number(value, example: str) -> str:
    """Why ``value`` is not a number (``Text``'s rules), and an example."""
    text = str(value)
    why = ("has an underscore: write the digits without '_'" if "_" in text else
           "has characters that are not ASCII" if not text.isascii() else
           "is below the smallest double (~5e-324) and would be read as 0" if _underflows(text) else
           "is beyond the range of a double (|x| < ~1.8e308) and would be read as infinity" if _overflows(text) else
           "is not a number")
    from ..errors import _shorten

    return f"{_shorten(repr(text))} {why}; give e.g. {example}"   # (10^5 characters were printed whole)


def quiet_heyoka() -> None:
    """heyoka's own warnings off (errors kept): a point that runs away gets the status ``nonfinite`` and says
    so; heyoka's '[warning] event detection skipped due to an invalid timestep value of nan' beside it on
    stderr was noise in a command's output (`slip --law '1-x'`, issue 21 walk 3)."""
    import heyoka

    heyoka.set_logger_level_error()


def _underflows(text: str) -> bool:
    """Whether ``text`` is a nonzero decimal that float() reads as 0 (``1e-400``)."""
    try:
        return float(text) == 0.0 and any(c in "123456789" for c in text.strip().lower().split("e")[0])
    except ValueError:
        return False


def _overflows(text: str) -> bool:
    """Whether ``text`` is a finite decimal that float() reads as ±inf (``1e400``)."""
    try:
        return math.isinf(float(text)) and "inf" not in text.lower()
    except ValueError:
        return False


class Whole(click.ParamType):
    """An integer option in ASCII digits (click's int() also reads '1_000' and '１'), in [low, high]."""

    name = "integer"

    def __init__(self, low: int | None = None, high: int | None = None, example: str = "10") -> None:
        self.low, self.high, self.example = low, high, example

    def convert(self, value, param, ctx):
        if isinstance(value, int) and not isinstance(value, bool):
            out = value
        else:
            text = str(value).strip()
            digits = text[1:] if text[:1] in "+-" else text
            if not (digits.isascii() and digits.isdigit()):
                why = _not_a_number(value, self.example).replace("is not a number", "is not a whole number")
                self.fail(why, param, ctx)
            if len(digits) > 30:   # int() refuses more than 4300 digits with a ValueError (a traceback)
                self.fail(f"a number of {len(digits)} digits is far outside [{self.low if self.low is not None else '-inf'}, "
                          f"{self.high if self.high is not None else 'inf'}]; give e.g. {self.example}", param, ctx)
            out = int(text)
        if (self.low is not None and out < self.low) or (self.high is not None and out > self.high):
            self.fail(f"{out} is not in [{self.low if self.low is not None else '-inf'}, "
                      f"{self.high if self.high is not None else 'inf'}]; give e.g. {self.example}", param, ctx)
        return out


class Real(click.ParamType):
    """A float option with ``Text``'s rules (ASCII, no '_')."""

    name = "number"

    def __init__(self, example: str = "1") -> None:
        self.example = example

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            return value
        from ..engine._exact import Text

        try:
            return float(Text(str(value)))
        except ValueError:
            self.fail(_not_a_number(value, self.example), param, ctx)


def number(name: str, example: str = "0.5"):
    """A click callback that parses a float itself, so a bad value gets our one-line message."""

    def convert(ctx, param, value):
        if value is None:
            return None
        from ..engine._exact import Text

        try:   # a float that keeps its text: a "quad" run reads the decimal in real128 (engine._exact)
            return Text(value)
        except ValueError:
            raise click.BadParameter(_not_a_number(value, example), param_hint=name) from None

    return convert


def check_out_dir(path: str, option: str = "--out") -> Path:
    """``path`` as a writable directory (created if missing), checked before any work is done."""
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise InputError(option, path, "is a file, not a directory", "give a directory (it is created if missing)")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(option, path, f"cannot be created ({exc.strerror or exc})",
                         "give a directory in a writable place") from None
    if not os.access(out, os.W_OK | os.X_OK):
        raise InputError(option, path, "is not writable", "give a directory you can write to")
    return out


def check_outside_stores(path, option: str = "--out", *, itself: bool = True) -> None:
    """Refuse ``path`` inside a bifurcation store (or, with ``itself``, the store itself): a store holds
    only what ``submit`` writes, and a report, an export or another store in it would be taken for damage
    or lost with it."""
    from ..store import store_kind

    here = Path(path).absolute()
    for place in ((here,) if itself else ()) + tuple(here.parents):
        if (place / "zarr.json").is_file() and store_kind(place) == "store":
            where = "is the store" if place == here else f"is inside the store {place}"
            raise InputError(option, str(path), where, "give a path outside every store, e.g. beside it")


def check_writable_dir(path, option: str = "--out") -> Path:
    """``path`` as a directory this process can write to or create, checked by making (and removing) an
    empty directory in it or in its nearest existing parent: a command that computes first must not fail
    at the end on its output (``/proc``, a read-only mount, a file in the way)."""
    import tempfile

    if not str(path).strip():   # Path("") is the working directory: a study would be written all over it
        raise InputError(option, str(path), "is empty", "give a directory, e.g. results/local/study")
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise InputError(option, str(path), "is a file, not a directory", "give a directory (it is created if missing)")
    check_outside_stores(out, option)
    parent = out.absolute()
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(option, str(path), f"cannot be created ({parent} is a file)",
                         "give a directory in a writable place")
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".bifurcation-probe-", dir=parent))
    except OSError as exc:
        what = "is not writable" if parent == out.absolute() else "cannot be created"
        raise InputError(option, str(path), f"{what} ({exc.strerror or exc} in {parent})",
                         "give a directory in a writable place") from None
    return out


def check_replace(out, names, *, given: bool, force: bool, option: str = "--out") -> None:
    """Refuse an ``out`` directory you named that holds an earlier output of this command (``names``),
    unless ``force``: a command replaces its own default output under results/local/ on a repeat run,
    never a directory you named (the same rule as ``export --out``). Checked before any work."""
    if not given or force:
        return
    found = [n for n in names if (Path(out) / n).exists() or (Path(out) / n).is_symlink()]
    if found:
        raise InputError(option, str(out), f"holds an earlier output ({', '.join(found)})",
                         "pass --force to replace it, or choose another directory")


@contextmanager
def native_stdout_to_stderr():
    """Send what native libraries print on file descriptor 1 (heyoka's and LLVM's warnings) to stderr.

    ``sys.stdout`` keeps the real standard output (a duplicate of fd 1), so only this program's own
    output (JSON, tables) is on stdout; worker processes started meanwhile inherit fd 1 = stderr too.
    """
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):   # no real fd 1 (embedded, some test runners)
        yield
        return
    original = sys.stdout
    os.dup2(2, 1)
    stream = io.TextIOWrapper(os.fdopen(saved, "wb"), encoding=getattr(original, "encoding", None) or "utf-8",
                              errors="replace", line_buffering=original.isatty() if hasattr(original, "isatty") else False)
    sys.stdout = stream
    status = None
    try:
        yield
    except SystemExit as exc:
        status = exc.code
        raise
    finally:
        lost = None
        try:
            stream.flush()
        except BrokenPipeError:   # the reader is gone (`| head`): nothing left to tell it
            pass
        except OSError as exc:    # `> /dev/full`, a full disk: the output is incomplete, so not a success
            lost = exc
        sys.stdout = original
        if lost is not None and status in (None, 0):
            click.echo(f"bifurcation: error: standard output: {lost.strerror or lost} (the output was not "
                       "written in full); write it where there is room", err=True)
            sys.exit(1)
