"""Bad input to a benchmark helper script: one line on stderr, exit status 2,
"nearcap: error (KIND): SCRIPT: ...", as nearcap's own commands write it
(docs/cli.md), never a traceback.

A script calls fail() where it knows what is wrong (the file and the field),
and runs its main through run(), which turns what a bad input raises
anywhere else into the same one line, naming the script's inputs: a file
that cannot be opened (io), text that is not the format or a value out of
range (parse), a field the input lacks or holds with the wrong type
(schema).
"""
import contextlib
import csv
import json
import os
import signal
import statistics
import sys


def fail(kind, message):
    script = os.path.basename(sys.argv[0])
    print(f"nearcap: error ({kind}): {script}: {' '.join(str(message).split())}", file=sys.stderr)
    sys.exit(2)


@contextlib.contextmanager
def reading(path, what):
    """Turns what reading `path` raises into fail()'s line; `what` names its
    format ("a sweep CSV"): a file that cannot be read (io), a column the
    rows lack (schema), text or a value that is not the format (parse)."""
    try:
        yield
    except OSError as e:
        fail("io", f"{path}: cannot read it ({e.strerror})")
    except KeyError as e:
        fail("schema", f"{path}: not {what} (no column {e})")
    except (ValueError, TypeError, RecursionError, csv.Error) as e:
        fail("parse", f"{path}: not {what} ({type(e).__name__}: {e})")


def read_json(path, what):
    """The JSON document in `path`, or fail()'s line: `what` names the format."""
    with reading(path, what), open(path, encoding="utf-8") as f:
        return json.load(f)


def run(main, inputs):
    """Exits with main()'s status (None: 0), or with fail()'s line naming
    `inputs` (the files main reads, as the user gave them)."""
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # quiet under `| head`
    try:
        status = main()
    except OSError as e:
        fail("io", f"{e.filename}: {e.strerror}" if e.filename else f"{inputs}: {e}")
    except (UnicodeDecodeError, csv.Error, json.JSONDecodeError) as e:
        fail("parse", f"{inputs}: not the format it reads ({e})")
    except RecursionError:
        fail("parse", f"{inputs}: nested too deeply to read")
    except (KeyError, IndexError, TypeError, AttributeError) as e:
        fail("schema", f"{inputs}: a field it reads is missing or of the wrong type ({type(e).__name__}: {e})")
    except (ValueError, ArithmeticError, statistics.StatisticsError) as e:
        fail("parse", f"{inputs}: a value it reads is not usable ({type(e).__name__}: {e})")
    except MemoryError:
        fail("resource", f"{inputs}: out of memory")
    sys.exit(status or 0)
