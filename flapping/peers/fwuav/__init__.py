"""FWUAV (fdcl-gwu/FWUAV): a quasi-steady multibody hover model, rebuilt from its equations.

- :mod:`~flapping.peers.fwuav.data`: the four insects' morphology, hover kinematics and FWUAV's
  stored results, as literals with their provenance (repository, commit, file, variable);
- :mod:`~flapping.peers.fwuav.model`: the prescribed-attitude translational equations of motion
  (wing and abdomen inertia, Sane & Dickinson's quasi-steady force, gravity);
- :mod:`~flapping.peers.fwuav.attitude`: the thorax pitch free (the planar reduction of FWUAV's
  attitude-free hover), :func:`pitch_free_floquet`;
- :mod:`~flapping.peers.fwuav.attitude3d`: the thorax attitude free in 3-D (FWUAV's
  ``eom_hover_xR``), :func:`attitude_free_floquet`: the lateral multipliers too;
- :mod:`~flapping.peers.fwuav.floquet`: :func:`hover_floquet`, the periodic hover orbit by our
  shooting and its Floquet exponents from our variational equations;
- :mod:`~flapping.peers.fwuav.cli`: the ``fwuav`` subcommand of ``python -m flapping``.

The book's chapter "A second model" compares its exponents with FWUAV's stored ones.
"""

from flapping.peers.fwuav.attitude import (
    DEFAULT_TRIM,
    TRIM_PARAMETERS,
    FwuavPitchFree,
    PitchFreeFloquet,
    pitch_free_floquet,
    pitch_free_model,
)
from flapping.peers.fwuav.attitude3d import (
    AttitudeFreeFloquet,
    FwuavAttitudeFree,
    attitude_free_floquet,
)
from flapping.peers.fwuav.data import (
                                       MONARCH_DOCUMENT,
                                       SPECIES,
                                       Kinematics,
                                       Morphology,
                                       Species,
                                       species,
)
from flapping.peers.fwuav.floquet import NAMES, HoverFloquet, fwuav_procedure, hover_floquet
from flapping.peers.fwuav.model import FwuavHover, Motion, prescribed_motion, wing_angles

__all__ = ["SPECIES", "NAMES", "Species", "Morphology", "Kinematics", "species", "FwuavHover",
           "Motion", "prescribed_motion", "wing_angles", "HoverFloquet", "hover_floquet",
           "fwuav_procedure", "FwuavPitchFree", "PitchFreeFloquet", "pitch_free_floquet",
           "MONARCH_DOCUMENT", "FwuavAttitudeFree", "AttitudeFreeFloquet",
           "attitude_free_floquet", "pitch_free_model", "TRIM_PARAMETERS", "DEFAULT_TRIM"]
