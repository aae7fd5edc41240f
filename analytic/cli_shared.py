"""What every command line shares: its exit codes, its checks before any work, its progress bars.

The command lines themselves are ``analytic/cli.py`` (``python -m analytic``)
and each package's ``cli.py``; they all import this module, which imports
nothing of theirs. Every command that writes files takes its paths through
here (``--out``, ``--report``, ``--plot``), so that a path that cannot be
written is refused at once, as a one-line message and exit code 2, rather
than as a traceback after minutes of simulation; and so that the path a
command prints is the path it writes. Every progress bar is made here
(``progress_bar``), so that each behaves the same on a terminal and in a
log file. Plain ``pathlib`` and ``os`` (and tqdm for the bars); nothing
here computes anything.
"""

from __future__ import annotations

import argparse
import gc
import os
import re
import sys
from pathlib import Path

#: Exit codes of every command line (``python -m analytic``, ``engine_model``, ``crosscheck``,
#: ``benchmarks``): it did its work (a throw; the models agree; every chunk shot) ...
EXIT_OK = 0
#: ... it ran but its result fails the command's check (the models or paths disagree, a sweep's
#: chunks failed, the engine raised) ...
EXIT_FAILED = 1
#: ... an input was refused before any work (a design, an option, an output path) ...
EXIT_INVALID = 2
#: ... the design is valid but does not throw ...
EXIT_NO_THROW = 3
#: ... or the user interrupted it (Ctrl-C: 128 + SIGINT, the shell's convention).
EXIT_INTERRUPTED = 130
#: ... or its reader went away (``... | head -1``): 128 + SIGPIPE, what the shell reports for a
#: program that the signal ended.
EXIT_PIPE_CLOSED = 141

#: Figure formats the Agg canvas writes without any other program.
PLOT_FORMATS = (".png", ".pdf", ".svg")
#: A token that is a negative number (``-1e-4``, ``-.5``, ``-inf``): an option's value, not an option.
_NEGATIVE_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


class OutputPathError(ValueError):
    """An output path that cannot be written; the message says which, why and what to do."""


def _existing_ancestor(path: Path) -> Path:
    for candidate in (path, *path.parents):
        if candidate.exists():
            return candidate
    return Path(".")


def _check_creatable(option: str, given: str, folder: Path) -> None:
    """``folder`` exists as a writable folder afterwards, or OutputPathError."""
    ancestor = _existing_ancestor(folder)
    if not ancestor.is_dir():
        raise OutputPathError(f"{option} {given}: {ancestor} is a file, so nothing can be written under it; "
                              f"choose a path outside it")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise OutputPathError(f"{option} {given}: cannot create the folder {folder} ({error.strerror}); "
                              f"choose a folder you can write to") from None
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputPathError(f"{option} {given}: the folder {folder} is not writable; "
                              f"choose a folder you can write to")


def output_folder(given: str | os.PathLike, option: str = "--out") -> Path:
    """Check, and create, the folder a command will write into.

    Parameters
    ----------
    given : the folder as the user gave it.
    option : the option's name, for the message.

    Returns
    -------
    Path
        The folder, existing and writable.

    Raises
    ------
    OutputPathError
        It is an existing file, lies under a file, or cannot be created or written.
    """
    folder = Path(given)
    if folder.exists() and not folder.is_dir():
        raise OutputPathError(f"{option} {given}: is a file, not a folder; give a folder "
                              f"(it is created if missing)")
    _check_creatable(option, str(given), folder)
    return folder


def output_file(given: str | os.PathLike, option: str = "--plot", formats: tuple[str, ...] = PLOT_FORMATS) -> Path:
    """Check the path of one file a command will write, and create its folder.

    A path without an extension gets the first of ``formats`` (``shot`` ->
    ``shot.png``); the path returned is the one to write and to print.

    Parameters
    ----------
    given : the file as the user gave it.
    option : the option's name, for the message.
    formats : the extensions allowed, the default first.

    Returns
    -------
    Path
        The file's path, its extension one of ``formats``, its folder existing and writable.

    Raises
    ------
    OutputPathError
        An unsupported extension, an existing folder of that name, a folder
        under a file, or a folder that cannot be created or written.
    """
    path = Path(given)
    if not path.suffix:
        path = path.with_name(path.name + formats[0])
    elif path.suffix.lower() not in formats:
        raise OutputPathError(f"{option} {given}: cannot write {path.suffix} files; "
                              f"use one of {', '.join(formats)}")
    if path.is_dir():
        raise OutputPathError(f"{option} {given}: {path} is a folder; give a file name")
    _check_creatable(option, str(given), path.parent)
    return path


def run_main(main) -> int:
    """``main()``'s exit code; quietly ``EXIT_PIPE_CLOSED`` where its output's reader went away.

    Python ignores SIGPIPE, so a write to a closed pipe raises ``BrokenPipeError``, there
    or at the final flush. The rest of the output goes to ``os.devnull``, so that the
    interpreter's own flush at exit finds nothing left to write.
    """
    try:
        code = main()
        sys.stdout.flush()
        return code
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_PIPE_CLOSED


def read_command_line(parser: argparse.ArgumentParser, argv: list[str] | None = None) -> argparse.Namespace:
    """``parser``'s reading of ``argv``, or of the process's own command line (``sys.argv[1:]``)
    if None, with negative numbers as values (``negative_numbers_as_values``).

    Reading the process's own command line, it then moves the objects that exist by
    then (the imported modules: numpy, scipy, numba, pymunk, the tools' own) out of the
    garbage collector's sight (``gc.freeze``): they live as long as the process, yet each
    full collection walked all of them again, a large share of a short command's time
    (the optimiser's default run timed whole, with and without the freeze); a
    process that runs one command and exits loses nothing by it. A caller that passes ``argv`` (a test, in its own long process)
    keeps its collector as it was.
    """
    args = parser.parse_args(negative_numbers_as_values(sys.argv[1:] if argv is None else list(argv)))
    if argv is None:
        gc.freeze()
    return args


def negative_numbers_as_values(argv: list[str]) -> list[str]:
    """``["--dt", "-1e-4"]`` as ``["--dt=-1e-4"]``, so that argparse reads a negative
    number as the option's value (and its own check rejects it) instead of as an
    unknown option, which it reports as "expected one argument"."""
    joined: list[str] = []
    for token in argv:
        if (joined and joined[-1].startswith("--") and "=" not in joined[-1]
                and _NEGATIVE_NUMBER.match(token)):
            joined[-1] = f"{joined[-1]}={token}"
        else:
            joined.append(token)
    return joined


def positive_int(text: str) -> int:
    """argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text} must be at least 1")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number above 0."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not 0.0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"{text} must be a positive number")
    return value


def units_argument(parser: argparse.ArgumentParser, what: str = "the printed text",
                   default: str = "the units the design file is mostly written in, else metric") -> None:
    """``--units metric|imperial``: the units of ``what``; JSON and CSV stay SI. Its default (None) is
    resolved by the command (``analytic.design_file.chosen_units``); ``default`` says how, for --help."""
    parser.add_argument("--units", choices=("metric", "imperial"), default=None,
                        help=f"units of {what} and of bare numbers on the command line (imperial: ft, lb, "
                             f"ft/s, lbf); JSON and CSV stay SI. Default: {default}")


#: Seconds between the lines of a progress bar written to a file or a pipe (not a terminal).
LOG_INTERVAL = 5.0


class _Lines:
    """A text stream for tqdm that writes each state of the bar as a line of its own: tqdm redraws
    its bar in place with carriage returns, which a log file or pipe keeps as one endless line."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, text: str) -> None:
        for line in text.replace("\r", "\n").split("\n"):
            if line.strip():   # tqdm clears a finished bar with spaces: nothing to keep
                self.stream.write(line.rstrip() + "\n")

    def flush(self) -> None:
        self.stream.flush()


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError):   # no isatty, or a closed stream
        return False


def progress_bar(iterable=None, **options):
    """A tqdm progress bar on stderr (or ``options["file"]``): redrawn in place on a terminal, and
    elsewhere (a file, a pipe, CI's log) a line every ``LOG_INTERVAL`` s and one at the end."""
    from tqdm import tqdm

    stream = options.pop("file", None) or sys.stderr
    if not _is_terminal(stream):
        stream = _Lines(stream)
        options["mininterval"] = max(options.get("mininterval", 0.0), LOG_INTERVAL)
    return tqdm(iterable, file=stream, **options)
