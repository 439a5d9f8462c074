"""Other groups' flapping-flight models, written inside the package to check ours against.

A peer model is rebuilt from its authors' published equations and data (never by translating
their code line by line), with the numbers it needs stored here as Python literals next to their
provenance, so that a user needs neither the peer's language nor a copy of its repository.

- :mod:`flapping.peers.fwuav`: FWUAV (fdcl-gwu, MATLAB), a quasi-steady multibody model of a
  hovering insect with its body attitude prescribed; hover orbits and Floquet exponents of a
  hawkmoth, a bumblebee, a fruit fly and a monarch.

This layer is built on :mod:`flapping.periodic` only: it imports nothing from
:mod:`flapping.model`, :mod:`flapping.hover` or :mod:`flapping.studies`.
"""
