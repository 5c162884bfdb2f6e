"""The physics of one asperity (Sec. 2), of interaction between asperities (Sec. 3), of the size
distribution (Eq. 30) and of the surface's power spectrum, as power laws in the contact area, and a
spectrum as measured (`MeasuredSpectrum`); the
choices among them (interactions, distributions, spot stiffnesses) are small `eqx.Module`s."""

from ._asperity import REGIMES, interference, kogut_etsion_laws, regime_edges, regime_load_laws
from ._distribution import (
    AbstractDistribution,
    MajumdarBhushan,
    WangKomvopoulos,
    size_distribution,
    wang_komvopoulos_psi,
)
from ._in_service import AbstractStiffness, Loading, TangentialStick, Unloading, mindlin_ratio
from ._interaction import AbstractInteraction, NoInteraction, PaperInteraction, SeriesInteraction, interaction_ratio
from ._measured_spectrum import AbstractLongEnd, MeasuredSpectrum, PowerLawEnd, Rolloff
from ._spot_stiffness import AbstractSpotStiffness, FamilyDerivative, Sneddon, hertz_stiffness
from ._summit_law import AbstractSummitLaw, HertzSummits, KogutEtsionSummits, SummitBands

__all__ = [
    "AbstractDistribution",
    "AbstractInteraction",
    "AbstractLongEnd",
    "AbstractSpotStiffness",
    "AbstractStiffness",
    "AbstractSummitLaw",
    "FamilyDerivative",
    "hertz_stiffness",
    "HertzSummits",
    "interaction_ratio",
    "interference",
    "kogut_etsion_laws",
    "KogutEtsionSummits",
    "Loading",
    "mindlin_ratio",
    "MajumdarBhushan",
    "MeasuredSpectrum",
    "NoInteraction",
    "PaperInteraction",
    "PowerLawEnd",
    "regime_edges",
    "regime_load_laws",
    "REGIMES",
    "Rolloff",
    "SeriesInteraction",
    "size_distribution",
    "Sneddon",
    "SummitBands",
    "TangentialStick",
    "Unloading",
    "wang_komvopoulos_psi",
    "WangKomvopoulos",
]
