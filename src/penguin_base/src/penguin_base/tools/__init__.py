"""The command-line tools of penguin_base: benchmarks, evaluations and mains.

Each module is named as its wrapper (scripts/<name> or nodes/<name>) and has
`main(argv=None) -> int`; beside them sit the modules only the tools use. Library code never
imports from here."""
