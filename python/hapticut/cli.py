"""The commands the hapticut executable hands to Python: `python3 -m hapticut.cli batch|plot ARGS`. A
module of its own, which the package does not import, so that running it as __main__ leaves the
package's modules (whose functions Dask's workers unpickle by name) as they are."""

import importlib
import sys

_COMMANDS = {"batch": "hapticut.batching", "plot": "hapticut.plotting"}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in _COMMANDS:
        print(f"usage: python3 -m hapticut.cli {{{','.join(_COMMANDS)}}} ARGS", file=sys.stderr)
        return 2
    return importlib.import_module(_COMMANDS[argv[0]]).main(argv[1:])


if __name__ == "__main__":
    sys.exit(main())
