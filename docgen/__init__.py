"""docgen: the generated parts of crd's documentation, and the check that they are current.

Results tables, pasted command output, the CAN contract and the CLI reference
are written between markers (:mod:`docgen.markers`) by the renderers in
:data:`docgen.blocks.BLOCKS`. ``python -m docgen`` rewrites them; ``python -m
docgen --check`` fails when any differs from a fresh render, and
``tests/docs/test_generated_docs.py`` runs that check in CI. Not installed with
crd: it is run from the repository.
"""
