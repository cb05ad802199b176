"""A finished study's statistics (:mod:`.stats`), Figures 10-20 (:mod:`.figures`) and
``report.md`` (:mod:`.report`)."""
