"""What the algorithms, the evaluation and the commands share: argument checks and callbacks."""
