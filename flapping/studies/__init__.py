"""Studies built on the hover orbit (the application layer above :mod:`flapping.hover`).

- :mod:`flapping.studies.sweep`: the hover orbit and its multipliers over grids of insect
  parameters, in process or on any executor;
- :mod:`flapping.studies.atlas`: the species atlas (homotopy between insects, Floquet against
  averaging across species);
- :mod:`flapping.studies.control`: what would make hover stable (the wing hinge's height, the
  mean stroke angle) and feedback once per wingbeat;
- :mod:`flapping.studies.cfd`: Sun's group's CFD stability derivatives as data, our model on
  their insect term by term, and which term decides the mode type;
- :mod:`flapping.studies.sensitivity`: the verdict's uncertainty, globally (Sobol indices over
  the uncertain inputs, SALib);
- :mod:`flapping.studies.explorer`: the grid behind the book's interactive stability map;
- :mod:`flapping.studies.lateral`: the presets in six degrees of freedom, their lateral modes
  beside the published ones.

Each imports :mod:`flapping.hover` and the layers below it; of the other studies only the batch
tool, :mod:`flapping.studies.sweep`.
"""
