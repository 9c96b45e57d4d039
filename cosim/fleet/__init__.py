"""Several equipped vehicles in one scene (``crd fleet``, issue 23): the fleet file (:mod:`.config`), the
other cars as objects of each car's scene (:mod:`.bodies`), the lock-step (:mod:`.lockstep`), the dance
metrics (:mod:`.dance_metrics`), the outputs (:mod:`.output`, :mod:`.plots`, :mod:`.report`,
:mod:`.scene_file`) and the bird's-eye video (:mod:`.run_view`, :mod:`.video`). Bundled scenes: ``scenes/``.
"""
