"""`ballimpact data list|copy`: the package's own data sets (`datasets`), which every verb's file
arguments also take as `builtin:NAME`."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any
from .common import add_json, print_lines


def add_parser(verbs) -> None:
    data = verbs.add_parser(
        "data", help="list the built-in data sets, or copy one out",
        description="The package's own data: the sample test, the speed set, Treloar's three "
                    "rubber tests and Kharaz's oblique rebounds. Any verb's file argument takes "
                    "one as builtin:NAME (e.g. `ballimpact features builtin:sample`, "
                    "`ballimpact fit builtin:speed-set --model single_element`), or one file of "
                    "a folder set as builtin:NAME/FILE.")
    steps = data.add_subparsers(dest="step", required=True, metavar="STEP")
    listing = steps.add_parser("list", help="the data sets: name, what it is, source, files",
                               description="The built-in data sets.")
    add_json(listing)
    copy = steps.add_parser("copy", help="copy a data set's files into a folder",
                            description="Copy the files of a built-in data set (a record with "
                                        "its side file; a folder set as a folder) into DEST.")
    copy.add_argument("name", metavar="NAME", help="the data set (see `ballimpact data list`)")
    copy.add_argument("dest", nargs="?", type=Path, default=Path("."), metavar="DEST",
                      help="folder to copy into (default: the current folder; made if its "
                           "parent exists)")
    copy.add_argument("--force", action="store_true", help="overwrite files that exist")
    add_json(copy)


def run(args: argparse.Namespace) -> dict[str, Any]:
    from ..records import datasets
    from ..records.text import datasets_lines

    if args.step == "list":
        sets = [d.to_dict() for d in datasets.DATASETS.values()]
        if not args.json:
            print_lines(datasets_lines(sets))
        return {"datasets": sets, "folder": str(datasets.DATA)}
    name = args.name[len(datasets.PREFIX):] if datasets.is_builtin(args.name) else args.name
    written = datasets.copy(name, args.dest, overwrite=args.force)
    if not args.json:
        print_lines(map(str, written))
    return {"name": datasets.get(name).name, "dest": str(args.dest),
            "files": [str(p) for p in written]}
