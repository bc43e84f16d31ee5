"""The command line the examples share: ``[OUT_FOLDER] [--depth D]`` and the example's
own ``--NAME N`` options, the output folder made when missing.

(The classic part parses its line by hand, so a one-shot run against the Rust example
never imports argparse and pathlib; see examples/python/classic_part.py.)
"""

import argparse
import pathlib


def command_line(doc, depth, **options):
    """Parses the example's command line: ``OUT_FOLDER`` (default example-output/python/,
    made here) as ``args.out`` (a ``pathlib.Path``), ``--depth`` (default ``depth``) and a
    ``--NAME`` for each keyword ``NAME=default`` (of the default's type); the help's
    description is the first line of ``doc`` (the example's ``__doc__``)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("out", nargs="?", default="example-output/python")
    parser.add_argument("--depth", type=int, default=depth)
    for name, default in options.items():
        parser.add_argument(f"--{name}", type=type(default), default=default)
    args = parser.parse_args()
    args.out = pathlib.Path(args.out)
    args.out.mkdir(parents=True, exist_ok=True)
    return args
