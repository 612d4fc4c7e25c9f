"""What things are: skeletons, timed event graphs, P/T nets, SDF graphs, arc lists,
the construction of a skeleton's timed event graph (spec §2), and the conversions
between them. Nothing here reads a file or analyzes."""
