"""``python -m jointplay``: the same command line as ``jointplay``."""

from jointplay.cli import main

if __name__ == "__main__":
    main()
