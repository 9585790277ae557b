"""The commands of ``pkm``, in the order ``pkm --help`` lists them. A command is a module of this package
that holds ``HELP`` (its one-line description), ``PARALLEL`` (whether its work may go to a Dask scheduler),
``options(parser)`` (its options, beside ``--json`` which every command takes) and ``run(args)``; a new
command is its module and its name here."""

from pkm.cli.commands import (
    atlas,
    build,
    calibrate,
    certify,
    compare,
    design,
    eval,
    explore,
    export,
    fk,
    index,
    list,
    pareto,
    reproduce,
    show,
    sweep,
    synth,
    tolerance,
)

COMMANDS = (list, build, eval, fk, certify, index, atlas, sweep, synth, pareto, show, compare, explore, design,
            tolerance, calibrate, export, reproduce)
