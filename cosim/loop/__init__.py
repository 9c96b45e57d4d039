"""Where simulated time advances: the closed loop (:mod:`.master`) and runs of several strategies (:mod:`.experiment`)."""
