"""Which runs a study makes: the training set-ups (:mod:`.setups`) and the plan (:mod:`.plan`)."""
