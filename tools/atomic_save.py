"""Charts and text written by raybench's one output rule (core/output_file.hpp): a regular file or a
new path is written whole or not at all (a hidden temporary beside it, renamed over it once
complete); a symlink is followed to its final target, and the temporary goes beside that target;
a FIFO or a character device is written directly, with no temporary; a directory, a socket or a
block device is refused. SIGTERM and SIGINT end the script through Python's exit path, so an
interrupted chart leaves no temporary behind."""
import os
import signal
import stat
import sys


def _stop(signum, _frame):
    sys.exit(128 + signum)


signal.signal(signal.SIGTERM, _stop)
signal.signal(signal.SIGINT, _stop)


def _destination(path):
    """(where the bytes go, whether they go there directly)."""
    target = os.path.realpath(path)  # every link followed, a dangling one's target included
    try:
        mode = os.stat(target).st_mode
    except FileNotFoundError:
        return target, False
    if stat.S_ISREG(mode):
        return target, False
    if stat.S_ISFIFO(mode) or stat.S_ISCHR(mode):
        return target, True
    raise OSError(f"cannot write {path}: not a file, a FIFO or a character device")


def _write(path, fill, binary):
    target, direct = _destination(path)
    if direct:
        with open(target, "wb" if binary else "w") as f:
            fill(f)
        return
    folder, name = os.path.split(target)
    tmp = os.path.join(folder, f".{name}.tmp-{os.getpid()}")
    try:
        with open(tmp, "wb" if binary else "w") as f:
            fill(f)
        if os.path.exists(target):
            os.chmod(tmp, stat.S_IMODE(os.stat(target).st_mode))
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def savefig(fig, path, **kwargs):
    fmt = os.path.splitext(path)[1][1:] or "png"
    _write(path, lambda f: fig.savefig(f, format=fmt, **kwargs), binary=True)


def write_text(path, text):
    _write(path, lambda f: f.write(text), binary=False)
