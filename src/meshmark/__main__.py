"""``python -m meshmark``: the same command line as ``meshmark``."""
from .cli import main

if __name__ == "__main__":
    main(prog_name="meshmark")
