"""``python -m railwear``: the ``railwear`` command."""

from railwear.cli import main

main()
