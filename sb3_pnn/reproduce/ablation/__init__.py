"""The set-up ablation (``python -m sb3_pnn.reproduce --ablation``): its cells and tasks
(:mod:`.catalog`), the command (:mod:`.cli`) and its table (:mod:`.report`)."""
