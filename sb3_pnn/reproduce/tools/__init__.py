"""Command-line tools that read study folders (``python -m sb3_pnn.reproduce.tools.<name>``):
:mod:`.same_runs` (are two folders' runs identical?), :mod:`.compare_studies`,
:mod:`.run_shapes`, :mod:`.spnn_switch_distance` and :mod:`.validation_trace`."""
