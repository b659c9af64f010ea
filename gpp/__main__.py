"""`python -m gpp`: the same as the `gpp` command."""

from gpp.cli.main import main

if __name__ == "__main__":
    main()
