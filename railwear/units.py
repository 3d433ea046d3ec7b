"""Unit conversions at the edges (layer 0): everything inside railwear is SI.

Scenario fields, command-line options, summaries and figure axes carry their unit in the name
(``speed_kmh``, ``static_load_kN``); they are converted here and nowhere else.
"""

KMH_PER_M_S = 3.6  # km/h per m/s (convert with the functions below, which divide by it)
KM = 1e3  # m per km
MM = 1e-3  # m per mm
UM = 1e-6  # m per µm
KN = 1e3  # N per kN
GPA = 1e9  # Pa per GPa
UG = 1e-9  # kg per µg
MM2 = 1e-6  # m² per mm²
MM3 = 1e-9  # m³ per mm³
PM = 1e-12  # m per pm
MN = 1e6  # N per MN
HOUR = 3600.0  # s per h


def kmh_to_m_s(v):
    """Speed from km/h to m/s (numbers, arrays or lists)."""
    return [x / KMH_PER_M_S for x in v] if isinstance(v, list) else v / KMH_PER_M_S


def m_s_to_kmh(v):
    """Speed from m/s to km/h (numbers, arrays or lists)."""
    return [x * KMH_PER_M_S for x in v] if isinstance(v, list) else v * KMH_PER_M_S
