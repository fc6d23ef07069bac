"""Charts written whole or not at all, as raybench writes its files: the image goes to a hidden
temporary beside the target, renamed over it once complete; SIGTERM and SIGINT end the script
through Python's exit path, so an interrupted chart leaves no temporary behind."""
import os
import signal
import sys


def _stop(signum, _frame):
    sys.exit(128 + signum)


signal.signal(signal.SIGTERM, _stop)
signal.signal(signal.SIGINT, _stop)


def savefig(fig, path, **kwargs):
    folder, name = os.path.split(path)
    tmp = os.path.join(folder, f".{name}.tmp-{os.getpid()}")
    try:
        fig.savefig(tmp, format=os.path.splitext(name)[1][1:] or "png", **kwargs)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def write_text(path, text):
    folder, name = os.path.split(path)
    tmp = os.path.join(folder, f".{name}.tmp-{os.getpid()}")
    try:
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
