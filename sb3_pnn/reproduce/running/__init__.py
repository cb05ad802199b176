"""Running a study's plan: one run's work (:mod:`.work`, :mod:`.recorder`), the parallel,
resumable executor (:mod:`.executor`) over the study folder (:mod:`.store`), reading the
results back (:mod:`.results`), and adopting runs of an earlier folder (:mod:`.adopt`)."""
