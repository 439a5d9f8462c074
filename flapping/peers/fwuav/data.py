"""FWUAV's four insects: morphology, optimised hover kinematics, stored hover exponents.

Every number below was read once (with ``scipy.io.loadmat``) from the FWUAV repository,
github.com/fdcl-gwu/FWUAV, at commit :data:`COMMIT`, directory :data:`DIRECTORY`:

- :class:`Morphology` from ``morp_<LABEL>.mat``, struct ``INSECT`` (fields ``l``, ``S``,
  ``cr_poly``, ``C_T``, ``C_D_0``, ``C_D_pi2``, ``m_B``, ``m_A``, ``m_R``, ``mu_R``, ``mu_A``,
  ``nu_R``, ``nu_A``, ``J_R``, ``J_B``, ``J_A``, ``scale``, ``rho``, ``g``); the same struct is
  stored again in each ``sim_QS_x_hover_<insect>.mat`` and is identical there;
- :class:`Kinematics` from ``sim_QS_x_hover_<insect>.mat``, struct ``WK`` (the wing, body and
  abdomen kinematics FWUAV's optimiser found for hover; ``WK.f`` differs from ``INSECT.f``);
- :attr:`Species.velocity_guess` from the same file, variable ``x_dot0`` (the initial velocity
  of FWUAV's hover trajectory, which starts at ``x0 = 0``);
- :attr:`Species.stored_exponents` from ``sim_QS_x_hover_conv_rate.mat``, variable
  ``conv_rate_<insect>``: FWUAV's Floquet exponents in 1/s, ordered as FWUAV's
  ``floquet_stability.m`` orders them (three zero position exponents, the two longitudinal ones
  in descending order, the lateral one last).

Units are SI as stored (m, m^2, kg, kg m^2, rad, Hz); ``chord_poly`` maps ``r / scale`` to
``c / scale`` (MATLAB ``polyval`` order, highest power first). Vectors are in FWUAV's frames:
``mu_*`` in the thorax frame (x forward, y right, z down), ``nu_R`` in the right-wing frame
(y along the span), ``nu_A`` in the abdomen frame; inertia tensors are row-major 3x3, the wing's
about its root. Only the masses and centre-of-mass offsets enter the prescribed-attitude
translational model; the inertia tensors are kept for reference.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["MONARCH_DOCUMENT", "COMMIT", "DIRECTORY", "REPOSITORY", "Morphology", "Kinematics",
           "Species", "SPECIES", "species"]

#: The FWUAV commit every number was read from.
COMMIT = "1a25d411fa8fad8d4d73c1089b2761505e280f42"
#: Its repository.
REPOSITORY = "https://github.com/fdcl-gwu/FWUAV"
#: The directory of the data files in that commit.
DIRECTORY = "matlab/sim_data/other_insects"


@dataclass(frozen=True)
class Morphology:
    """FWUAV's ``INSECT`` struct: what the translational hover model needs (SI units).

    Attributes
    ----------
    label : str
        ``INSECT.name``.
    scale : float
        Length unit of ``chord_poly`` (m).
    rho, g : float
        Air density (kg/m^3) and gravity (m/s^2).
    span, area : float
        Length ``l`` (m) and area ``S`` (m^2) of one wing.
    coefficients : str
        ``"sane-dickinson"`` (``C_L = C_T sin 2a``, ``C_D = C_D_0 cos^2 a + C_D_pi2 sin^2 a``) or
        ``"monarch"`` (FWUAV's fitted monarch curves, which have no ``C_T``).
    C_T, C_D_0, C_D_pi2 : float or None
        Sane & Dickinson coefficients (None for the monarch).
    m_B, m_A, m_wing : float
        Masses of the thorax, the abdomen and one wing (kg).
    chord_poly : tuple of float
        Chord polynomial ``c(r) / scale`` of ``r / scale``, highest power first.
    mu_R, mu_A : tuple of float
        Right-wing root and abdomen joint from the thorax centre of mass, thorax frame (m).
    nu_R, nu_A : tuple of float
        Right-wing centre of mass from its root (wing frame) and abdomen centre of mass from its
        joint (abdomen frame) (m).
    J_R, J_B, J_A : tuple of float
        Inertia tensors (row-major) of the right wing about its root, the thorax and the abdomen
        (kg m^2); not used by the translational model.
    """

    label: str
    scale: float
    rho: float
    g: float
    span: float
    area: float
    coefficients: str
    C_T: float | None
    C_D_0: float | None
    C_D_pi2: float | None
    m_B: float
    m_A: float
    m_wing: float
    chord_poly: tuple[float, ...]
    mu_R: tuple[float, ...]
    mu_A: tuple[float, ...]
    nu_R: tuple[float, ...]
    nu_A: tuple[float, ...]
    J_R: tuple[float, ...]
    J_B: tuple[float, ...]
    J_A: tuple[float, ...]

    @property
    def mass(self) -> float:
        """Total mass ``m_B + m_A + 2 m_wing`` (kg)."""
        return self.m_B + self.m_A + 2.0 * self.m_wing


@dataclass(frozen=True)
class Kinematics:
    """FWUAV's ``WK`` struct for hover (Berman & Wang's wing kinematics; rad, Hz).

    Flapping ``phi = phi_m / asin(phi_K) asin(phi_K cos wt) + phi_0``; pitch
    ``theta = theta_m / tanh(theta_C) tanh(theta_C sin(wt + theta_a)) + theta_0``; deviation
    ``psi = psi_m cos(psi_N wt + psi_a) + psi_0``; thorax pitch
    ``theta_B = theta_B_m cos(wt + theta_B_a) + theta_B_0``; abdomen pitch relative to the thorax
    ``theta_A = theta_A_m cos(wt + theta_A_a) + theta_A_0``; ``w = 2 pi f``; ``beta`` is the
    stroke-plane angle relative to the thorax.
    """

    f: float
    beta: float
    phi_m: float
    phi_K: float
    phi_0: float
    theta_m: float
    theta_C: float
    theta_0: float
    theta_a: float
    psi_m: float
    psi_N: int
    psi_a: float
    psi_0: float
    theta_B_m: float
    theta_B_0: float
    theta_B_a: float
    theta_A_m: float
    theta_A_0: float
    theta_A_a: float


@dataclass(frozen=True)
class Species:
    """One of FWUAV's insects: morphology, hover kinematics, FWUAV's results, provenance.

    Attributes
    ----------
    name : str
        Our name (``hawkmoth``, ``bumblebee``, ``fruit_fly``, ``monarch``).
    morphology : Morphology
    kinematics : Kinematics
    velocity_guess : tuple of float
        FWUAV's initial velocity ``x_dot0`` of its hover trajectory (m/s, inertial, z down).
    stored_exponents : tuple of float
        FWUAV's Floquet exponents (1/s): three position zeros, two longitudinal, one lateral.
    hover_file, morphology_file, exponents_variable : str
        Where they come from, in :data:`DIRECTORY` at :data:`COMMIT`.
    """

    name: str
    morphology: Morphology
    kinematics: Kinematics
    velocity_guess: tuple[float, ...]
    stored_exponents: tuple[float, ...]
    hover_file: str
    morphology_file: str
    exponents_variable: str

    @property
    def provenance(self) -> str:
        """Repository, commit and files of this insect's numbers."""
        return (f"{REPOSITORY} @ {COMMIT[:7]}: {DIRECTORY}/{self.morphology_file} (INSECT), "
                f"{DIRECTORY}/{self.hover_file} (WK, x_dot0), "
                f"{DIRECTORY}/sim_QS_x_hover_conv_rate.mat ({self.exponents_variable})")


SPECIES: dict[str, Species] = {
    "hawkmoth": Species(
        name="hawkmoth",
        morphology=Morphology(
            label="HAWKMOTH", scale=0.01, rho=1.225, g=9.81, span=0.0519,
            area=0.0009445118509019482,
            coefficients="sane-dickinson", C_T=1.678, C_D_0=0.07, C_D_pi2=3.06,
            m_B=0.0009324, m_A=0.0006216, m_wing=4.7e-05,
            chord_poly=(-0.0035261478823817457, 0.047581892329726934, -0.24115330076639993,
                0.5583364736082108, -0.6216007961017084, 0.20989740978157126, 2.318863994763827),
            mu_R=(0.0, 0.0049678390032496115, 0.0),
            mu_A=(-0.012795683911539053, 0.0, 0.0),
            nu_R=(0.0, 0.010955095020579111, 0.0),
            nu_A=(-0.01520088765430955, 0.0, 0.0),
            J_R=(3.1296923979951525e-08, -0.0, 0.0, -0.0, 1.5953494163992991e-09, 0.0, 0.0, 0.0,
                3.289227339635082e-08),
            J_B=(1.1505547637661413e-08, 0.0, 0.0, 0.0, 5.6639910737087926e-08, 0.0, 0.0, 0.0,
                5.6639910737087926e-08),
            J_A=(3.2724060255805623e-09, 0.0, 0.0, 0.0, 1.9314452057773617e-07, 0.0, 0.0, 0.0,
                1.9314452057773617e-07),
        ),
        kinematics=Kinematics(
            f=30.234258388462003, beta=0.49704104673144767,
            phi_m=0.8267610749353946, phi_K=0.20287832673153008, phi_0=-0.06595123207023218,
            theta_m=0.6977306858698092, theta_C=1.7007991684490393,
            theta_0=0.014132415817690171, theta_a=0.0851242619379555,
            psi_m=0.07418418318048726, psi_N=2, psi_a=-1.3047271154191156,
            psi_0=-4.500508845014507e-12,
            theta_B_m=0.028893879233254097, theta_B_0=1.0439977192726055,
            theta_B_a=-1.3900115179446861,
            theta_A_m=0.0384379372149469, theta_A_0=0.5495113119346647,
            theta_A_a=-3.614765252351664,
        ),
        velocity_guess=(-0.11981422138550234, 3.95256743308817e-19, 0.006147654793844691),
        stored_exponents=(0.0, 0.0, 0.0, -1.775520438088073, -4.628442302539322,
            -1.4813366750081522),
        hover_file="sim_QS_x_hover_hawk.mat",
        morphology_file="morp_HAWKMOTH.mat",
        exponents_variable="conv_rate_hawk",
    ),
    "bumblebee": Species(
        name="bumblebee",
        morphology=Morphology(
            label="BUMBLEBEE", scale=0.01, rho=1.225, g=9.81, span=0.013200000000000002,
            area=5.288582269831944e-05,
            coefficients="sane-dickinson", C_T=1.341, C_D_0=0.0, C_D_pi2=2.93,
            m_B=0.00010444799999999999, m_A=6.9632e-05, m_wing=4.6e-07,
            chord_poly=(-2.8680476461022706, 9.843150445037066, -12.68797157809191,
                7.47139262014114, -2.1155519536050225, 0.18168780818296826, 0.5105056549261072),
            mu_R=(0.0, 0.0023524900395989843, 0.0),
            mu_A=(-0.006059318535093863, 0.0, 0.0),
            nu_R=(0.0, 0.0027862669416501566, 0.0),
            nu_A=(-0.007198288184547596, 0.0, 0.0),
            J_R=(1.981411938722047e-11, -0.0, 0.0, -0.0, 7.567742587433024e-13, 0.0, 0.0, 0.0,
                2.0570893645963772e-11),
            J_B=(2.8901855099600275e-10, 0.0, 0.0, 0.0, 1.4227905915744313e-09, 0.0, 0.0, 0.0,
                1.4227905915744313e-09),
            J_A=(8.220261021631129e-11, 0.0, 0.0, 0.0, 4.851776832201378e-09, 0.0, 0.0, 0.0,
                4.851776832201378e-09),
        ),
        kinematics=Kinematics(
            f=126.72850747800466, beta=0.41373958294088115,
            phi_m=1.254056292456839, phi_K=0.5209498397429433, phi_0=-0.020120693158798733,
            theta_m=0.6731362712210929, theta_C=2.7405976591249046,
            theta_0=0.23136624355140634, theta_a=-0.3277412854358316,
            psi_m=0.02727351315600173, psi_N=2, psi_a=0.589676028809444,
            psi_0=-2.758719048503674e-13,
            theta_B_m=0.03809745992410827, theta_B_0=0.7323563227089595,
            theta_B_a=-1.4296083874116883,
            theta_A_m=0.04459847440930536, theta_A_0=0.6631848529064813,
            theta_A_a=-3.5242575930629725,
        ),
        velocity_guess=(-0.11689007196104508, -5.075336578994235e-20, -0.0709962529097329),
        stored_exponents=(0.0, 0.0, 0.0, -1.5289432327609633, -2.891965943183481,
            -2.011876953680958),
        hover_file="sim_QS_x_hover_bumb.mat",
        morphology_file="morp_BUMBLEBEE.mat",
        exponents_variable="conv_rate_bumb",
    ),
    "fruit_fly": Species(
        name="fruit_fly",
        morphology=Morphology(
            label="FRUITFLY", scale=0.001, rho=1.225, g=9.81, span=0.00202,
            area=1.348855578921783e-06,
            coefficients="sane-dickinson", C_T=1.833, C_D_0=0.21, C_D_pi2=3.35,
            m_B=4.3096799999999995e-07, m_A=2.87312e-07, m_wing=8.599999999999999e-10,
            chord_poly=(-0.3721949549587863, 1.954770072785033, -3.8559482242408727,
                3.4747054383794764, -1.5056276034877036, 0.19787781089246748, 0.8508427582101717),
            mu_R=(0.0, 0.0003769576915660712, 0.0),
            mu_A=(-0.0009709315189457081, 0.0, 0.0),
            nu_R=(0.0, 0.0004263832744040411, 0.0),
            nu_A=(-0.001153437443559563, 0.0, 0.0),
            J_R=(8.675015740775857e-16, -0.0, 0.0, -0.0, 3.930107865020541e-17, 0.0, 0.0, 0.0,
                9.06802652727791e-16),
            J_B=(3.061965176162229e-14, 0.0, 0.0, 0.0, 1.507354884092689e-13, 0.0, 0.0, 0.0,
                1.507354884092689e-13),
            J_A=(8.7088364744955e-15, 0.0, 0.0, 0.0, 5.140144690199067e-13, 0.0, 0.0, 0.0,
                5.140144690199067e-13),
        ),
        kinematics=Kinematics(
            f=285.2398051212711, beta=0.4683587731012854,
            phi_m=1.1612576141069677, phi_K=0.35447366814901954, phi_0=-0.004910704146422993,
            theta_m=0.6388635754119414, theta_C=2.172082947273504,
            theta_0=0.11911552688688054, theta_a=-0.22802031672295062,
            psi_m=0.023904893371399217, psi_N=2, psi_a=2.3759418851670326,
            psi_0=-0.00047250872957169517,
            theta_B_m=0.14240629631034146, theta_B_0=0.9019286436931124,
            theta_B_a=-1.448054534860683,
            theta_A_m=0.1780489970237613, theta_A_0=0.5951349066981263,
            theta_A_a=-3.42937588930133,
        ),
        velocity_guess=(-0.15889665831309607, -2.4266927169623586e-20, -0.07753585915984655),
        stored_exponents=(0.0, 0.0, 0.0, -3.9368558006579044, -7.035883894600251,
            -4.647854698974909),
        hover_file="sim_QS_x_hover_fruit.mat",
        morphology_file="morp_FRUITFLY.mat",
        exponents_variable="conv_rate_fruit",
    ),
    "monarch": Species(
        name="monarch",
        morphology=Morphology(
            label="MONARCH", scale=0.01, rho=1.225, g=9.81, span=0.060997,
            area=0.0012751313292703765,
            coefficients="monarch", C_T=None, C_D_0=None, C_D_pi2=None,
            m_B=0.0001485, m_A=0.0001092, m_wing=2.51e-05,
            chord_poly=(-0.00576011657642655, 0.09801704653624195, -0.5823242130209877,
                1.3617447947946397, -1.16264520306422, 1.5570547119172067, 0.1649147133033578),
            mu_R=(0.0, 0.00284, 0.0),
            mu_A=(-0.007315, 0.0, 0.0),
            nu_R=(-0.004437781694645591, 0.015176339407718576, 0.0),
            nu_A=(-0.00869, 0.0, 0.0),
            J_R=(2.756824953134474e-08, 2.4957003913366034e-09, 0.0, 2.4957003913366034e-09,
                2.579907487057571e-09, 0.0, 0.0, 0.0, 3.0148157018402314e-08),
            J_B=(5.988708000000001e-10, 0.0, 0.0, 0.0, 2.9481420375000006e-09, 0.0, 0.0, 0.0,
                2.9481420375000006e-09),
            J_A=(1.87879965e-10, 0.0, 0.0, 0.0, 1.1089084142499997e-08, 0.0, 0.0, 0.0,
                1.1089084142499997e-08),
        ),
        kinematics=Kinematics(
            f=11.721978058989183, beta=0.3056567165909269,
            phi_m=0.6072701152987067, phi_K=0.3077061347161513, phi_0=0.07800520119518113,
            theta_m=0.665659345838219, theta_C=1.4381845036113263,
            theta_0=0.1642100962452325, theta_a=-0.08963168351558072,
            psi_m=0.0017669220783796723, psi_N=2, psi_a=-0.41651879803962233,
            psi_0=0.029662739615687776,
            theta_B_m=0.2581912665375843, theta_B_0=0.921213172582787,
            theta_B_a=-1.3364485034436777,
            theta_A_m=0.190489578348287, theta_A_0=0.680628577395682,
            theta_A_a=-3.6185543638281943,
        ),
        velocity_guess=(-0.3068573417129557, -8.942511818317692e-19, -0.05432334443188191),
        stored_exponents=(0.0, 0.0, 0.0, -8.435460362807609, -12.84492058343153,
            -2.731445406992666),
        hover_file="sim_QS_x_hover_mona.mat",
        morphology_file="morp_MONARCH.mat",
        exponents_variable="conv_rate_mona",
    ),
}


def species(name: str) -> Species:
    """The FWUAV insect called ``name``.

    Parameters
    ----------
    name : str
        One of ``hawkmoth``, ``bumblebee``, ``fruit_fly``, ``monarch``.

    Returns
    -------
    Species

    Raises
    ------
    ValueError
        For another name; the message lists the four.
    """
    if not isinstance(name, str) or name not in SPECIES:
        raise ValueError(f"`name` must be one of {', '.join(SPECIES)}; got {name!r}")
    return SPECIES[name]


#: The monarch's hover exponents in FWUAV's ``doc/QS_model.tex`` (lines 2084-2085 at the
#: snapshot's HEAD ``04953d4``), added in commit ``fd1b156`` (2019-12-17), and what that commit's
#: ``matlab/floquet_stability.m`` computed them from: the hover file it loads
#: (``sim_QS_x_hover_multistart_vary_vel_and_freq_final_better_no_tol_correct_abdomen_osc_less_
#: freq.mat``, its ``WK``), its perturbation ``epsilon`` and the number of periods it integrates.
#: The stored exponents of :data:`SPECIES` come from ``sim_QS_x_hover_mona.mat`` at ``1a25d41``
#: (2020-09-28), whose ``WK`` is listed beside (``f``, ``beta``, ``phi_m``, ``theta_B_m``).
MONARCH_DOCUMENT: dict[str, object] = {
    "commit": "fd1b156",
    "date": "2019-12-17",
    "exponents": (0.0, 0.0, 0.0, -6.0349, -8.7958, -11.5706),
    "epsilon": 1.0,
    "periods": 10,
    "f": 11.628611693194877,
    "beta": 0.35478949579126245,
    "phi_m": 0.6775587460924892,
    "theta_B_m": None,  # the 2019 file has no body-pitch oscillation in WK
    "stored_commit": "1a25d41",
    "stored_f": 11.721978058989183,
    "stored_beta": 0.3056567165909269,
    "stored_phi_m": 0.6072701152987067,
    "stored_theta_B_m": 0.2581912665375843,
}
