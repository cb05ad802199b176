"""``python -m sb3_pnn.evaluate``: the command line of :mod:`sb3_pnn.evaluation` (its
``__main__``; ``python -m sb3_pnn.evaluation`` runs the same)."""

from sb3_pnn.evaluation.__main__ import main

if __name__ == "__main__":
    main()
