"""``python -m bifurcation`` runs the command line."""

from .cli import main

main()
