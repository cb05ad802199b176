"""Pictures: frames of an episode (:mod:`.frames`, ``render_mode="rgb_array"``), plots of
trajectories and layouts (:mod:`.plotting`) and a scripted demo (:mod:`.demo`)."""
