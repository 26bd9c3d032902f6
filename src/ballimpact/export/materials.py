"""Our materials in other codes' terms (SI in, the deck's units out).

ABAQUS (and CalculiX, which reads the same cards):

- Mooney-Rivlin: `*HYPERELASTIC, MOONEY-RIVLIN` C10, C01, D1; neo-Hookean: `*HYPERELASTIC, NEO
  HOOKE` C10, D1; Yeoh: `*HYPERELASTIC, YEOH` C10, C20, C30, D1, D2, D3 (D2 = D3 = 0: our
  volumetric energy is K/2 (J - 1)^2 alone); Ogden: `*HYPERELASTIC, OGDEN, N=n` mu_1, alpha_1, ...,
  mu_n, alpha_n, D_1, ..., D_n (D_2.. = 0; eight values a line; both codes write the energy
  2 mu_i / alpha_i^2 (lbar1^a_i + lbar2^a_i + lbar3^a_i - 3) + (J - 1)^2 / D_1 as we do; CalculiX
  reads N <= 3); Ogden hyperfoam: `*HYPERFOAM, N=n` mu_1, alpha_1, ..., mu_n, alpha_n, nu_1, ...,
  nu_n (eight values a line); linear elastic: `*ELASTIC` E, nu (ABAQUS integrates it
  hypoelastically at finite strain; we use Saint Venant-Kirchhoff: the same at small strain).
- `MODULI=LONG TERM|INSTANTANEOUS` carries our `moduli`; Prony terms are `*VISCOELASTIC,
  TIME=PRONY` rows g_i, k_i, tau_i. Hyperfoam relaxes as a whole with g_i: k_i = g_i is written.
- D1 = 0 is written as 0 for ABAQUS: ABAQUS/Explicit then takes K0 = 20 mu0, as we do. CalculiX
  has no such rule (D1 = 0 divides by zero), so its decks get D1 = 2 / K with our K (every rubber
  law: neo-Hookean, Mooney-Rivlin, Yeoh, Ogden).
- CalculiX has no Prony viscoelasticity for hyperelastic materials: its decks hold the elastic
  ball of the chosen moduli (long-term: deviatoric constants x (1 - sum g_i); instantaneous: as
  the solver uses them), and say so.

LS-DYNA (`*MAT_077`): `*MAT_HYPERELASTIC_RUBBER` (C10, C01, PR; Yeoh as C10, C20, C30 of its
polynomial card C10, C01, C11, C20, C02, C30) and `*MAT_OGDEN_RUBBER` for Ogden, and for
hyperfoam when every term has the same nu >= 0.45. LS-DYNA's Ogden energy is
sum_i sum_j mu_j / alpha_j (lbar_i^alpha_j - 1) plus a volumetric term from PR (initial shear
modulus sum mu_j alpha_j / 2), so mu_j(LS-DYNA) = 2 mu_j / alpha_j gives our energy at J = 1.
Its viscoelasticity is an added linear overstress, g(t) = sum G_i exp(-beta_i t), on long-term
hyperelastic constants: C10, C01, C20, C30 (mu_i) are written long-term, G_i = g_i mu0
(instantaneous mu0, e.g. 2 (C10 + C01) / (1 - sum g)), beta_i = 1 / tau_i. The two agree at small strain; bulk
relaxation (k_i) has no counterpart and is refused. LS-DYNA takes the bulk modulus from PR and
the shear modulus of the hyperelastic constants, which are the long-term ones here, so PR is
chosen to give our bulk modulus K (D1 = 0: K0 = 20 x the instantaneous mu0) from the long-term
mu: PR = (3K - 2 mu)/(2 (3K + mu)), 0.4948 for the universal ball (g = 0.79), 0.4754 without
Prony terms.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import InputError
from ..constitutive import (LinearElastic, Material, MooneyRivlin, NeoHookean, Ogden,
                            OgdenHyperfoam, Yeoh)
from .units import UnitSystem

CODES = ("abaqus", "calculix", "lsdyna")

#: smallest nu of a hyperfoam written as LS-DYNA's (deviatoric/volumetric split) Ogden rubber
LSDYNA_OGDEN_MIN_NU = 0.45
#: most Ogden terms CalculiX's *HYPERELASTIC, OGDEN reads (ABAQUS: 6, as our model)
CALCULIX_OGDEN_MAX_TERMS = 3
#: the rubber laws with a D1 (nearly incompressible: D1 = 0 means K0 = 20 mu0)
RUBBER = (NeoHookean, MooneyRivlin, Yeoh, Ogden)


class ExportError(InputError):
    """A ball that a code cannot express as asked (exit 2)."""


@dataclass
class Cards:
    """Keyword lines of one material and the notes that go to the header and to stderr."""

    lines: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def number(x: float) -> str:
    """A float with 12 significant digits, as short as the value allows."""
    return f"{x:.12g}"


def _rows(values: list[float], per_line: int = 8) -> list[str]:
    return [", ".join(number(v) for v in values[i:i + per_line])
            for i in range(0, len(values), per_line)]


def elastic_scale(material: Material, moduli: str) -> tuple[float, float]:
    """Factors from the constants as given to the elastic ball of `moduli` (deviatoric, bulk)."""
    dev = material.deviatoric_factor()
    vol = material.volumetric_factor()
    if moduli == "long_term":
        return dev * (1.0 - material.sum_g), vol * (1.0 - material.sum_bulk_relaxation)
    return dev, vol


def abaqus_material(name: str, density_kg_m3: float, material: Material, units: UnitSystem,
                    code: str = "abaqus", moduli: str | None = None) -> Cards:
    """`*MATERIAL` block of one layer for ABAQUS or CalculiX (`code`). For CalculiX `moduli`
    chooses the elastic ball written in place of a viscoelastic one (default: the material's)."""
    cards = Cards([f"*MATERIAL, NAME={name}", "*DENSITY", number(density_kg_m3 * units.density)])
    s = units.stress
    calculix = code == "calculix"
    viscous = bool(material.prony)
    dev, vol = (1.0, 1.0)
    # MODULI matters (and is written) only with a Prony series
    tag = f", MODULI={material.moduli.upper().replace('_', ' ')}" if viscous else ""
    if calculix:
        tag = ""
        if any(t.g or t.k for t in material.prony):
            chosen = moduli or material.moduli
            dev, vol = elastic_scale(material, chosen)
            cards.notes.append(
                f"{name}: CalculiX has no Prony viscoelasticity for hyperelastic materials; the "
                f"{chosen.replace('_', '-')} elastic ball is written (Prony terms "
                + ", ".join(f"g={t.g:g} tau={t.tau_s:g} s" for t in material.prony) + " dropped)")

    if isinstance(material, RUBBER):
        d1 = material.d1_per_pa
        if calculix and d1 == 0.0:  # CalculiX cannot read D1 = 0: write our K explicitly
            mu, k_given = material.given_moduli_pa()
            d1 = 2.0 / (k_given * vol)
            cards.notes.append(f"{name}: D1 = 0 written as D1 = 2/K with K = 20 mu0 "
                               f"({k_given * vol:.6g} Pa), the nearly incompressible bulk modulus "
                               "ABAQUS/Explicit substitutes")
        elif calculix:
            d1 = d1 / vol
        elif d1 == 0.0 and viscous:
            k = material.bulk_modulus_pa(True)
            cards.notes.append(
                f"{name}: D1 = 0 with MODULI={material.moduli.upper().replace('_', ' ')}: "
                f"ballimpact reads it as K0 = 20 x the instantaneous mu0 = {k:.6g} Pa, as "
                f"ABAQUS/Explicit's substitute; to pin it (or for ABAQUS/Standard) write "
                f"D1 = {2.0 / k / s:.6g} in the deck's units")
        d1_out = d1 / s
        if isinstance(material, MooneyRivlin):
            cards.lines += [f"*HYPERELASTIC, MOONEY-RIVLIN{tag}",
                            _rows([material.c10_pa * dev * s, material.c01_pa * dev * s, d1_out])[0]]
        elif isinstance(material, NeoHookean):
            cards.lines += [f"*HYPERELASTIC, NEO HOOKE{tag}",
                            _rows([material.c10_pa * dev * s, d1_out])[0]]
        elif isinstance(material, Yeoh):
            cards.lines += [f"*HYPERELASTIC, YEOH{tag}", _rows(
                [material.c10_pa * dev * s, material.c20_pa * dev * s, material.c30_pa * dev * s,
                 d1_out, 0.0, 0.0])[0]]
        else:
            n = len(material.terms)
            if calculix and n > CALCULIX_OGDEN_MAX_TERMS:
                raise ExportError(f"{name}: CalculiX's *HYPERELASTIC, OGDEN reads at most "
                                  f"{CALCULIX_OGDEN_MAX_TERMS} terms, the material has {n}")
            values = [v for t in material.terms for v in (t.mu_pa * dev * s, t.alpha)]
            values += [d1_out] + [0.0] * (n - 1)
            cards.lines += [f"*HYPERELASTIC, OGDEN, N={n}{tag}", *_rows(values)]
    elif isinstance(material, OgdenHyperfoam):
        values = [v for t in material.terms for v in (t.mu_pa * dev * s, t.alpha)]
        values += [t.nu for t in material.terms]
        cards.lines += [f"*HYPERFOAM, N={len(material.terms)}{tag}", *_rows(values)]
    elif isinstance(material, LinearElastic):
        mu, k = material.given_moduli_pa()
        mu, k = mu * dev, k * vol
        e = 9.0 * k * mu / (3.0 * k + mu)
        nu = (3.0 * k - 2.0 * mu) / (2.0 * (3.0 * k + mu))
        cards.lines += ["*ELASTIC" + ("" if calculix else tag), _rows([e * s, nu])[0]]
    else:  # a model added to constitutive but not here
        raise ExportError(f"{name}: material model {material.model!r} has no {code} card")
    if viscous and not calculix:
        cards.lines.append("*VISCOELASTIC, TIME=PRONY")
        whole = material.relax_whole_stress
        cards.lines += [_rows([t.g, t.g if whole else t.k, t.tau_s * units.time])[0]
                        for t in material.prony]
    return cards


# ---- LS-DYNA ---------------------------------------------------------------------------------
def lsdyna_material(mid: int, name: str, density_kg_m3: float, material: Material,
                    units: UnitSystem,
                    approximate: bool = False) -> tuple[str, list[list], list[str]]:
    """(keyword, cards as lists of values, notes) of `*MAT_077` for one layer. `approximate`
    writes the nearest card where the material has no exact counterpart (and says so); without
    it such a material raises `ExportError` naming it and what would be written."""
    s = units.stress
    notes: list[str] = []
    if any(t.k for t in material.prony) and not material.relax_whole_stress:
        raise ExportError(f"{name}: LS-DYNA *MAT_077 has no bulk (k_i) relaxation; set the "
                          "Prony k to 0 to export")
    long_dev = elastic_scale(material, "long_term")[0]   # constants as given -> long-term
    inst_mu = material.shear_modulus_pa(instantaneous=True)
    mu_long, k_long = material.shear_modulus_pa(False), material.bulk_modulus_pa(False)
    k_inst = material.bulk_modulus_pa(True)
    pr = (3.0 * k_long - 2.0 * mu_long) / (2.0 * (3.0 * k_long + mu_long))
    visco = [[t.g * inst_mu * s, 1.0 / (t.tau_s * units.time)] for t in material.prony]
    head = [mid, density_kg_m3 * units.density, pr, 0, len(visco), 0.0, 0.0, 0.0]
    if isinstance(material, (MooneyRivlin, NeoHookean, Yeoh)):
        c01 = material.c01_pa if isinstance(material, MooneyRivlin) else 0.0
        c20, c30 = (material.c20_pa, material.c30_pa) if isinstance(material, Yeoh) else (0.0, 0.0)
        # the polynomial card: C10, C01, C11, C20, C02, C30, THERML
        cards = [head, [material.c10_pa * long_dev * s, c01 * long_dev * s, 0.0,
                        c20 * long_dev * s, 0.0, c30 * long_dev * s, 0.0]]
        return "*MAT_HYPERELASTIC_RUBBER_TITLE", [*cards, *visco], notes
    if isinstance(material, Ogden):  # (at most 6 terms: the card holds 8)
        mus = [2.0 * t.mu_pa * long_dev / t.alpha * s for t in material.terms]
        alphas = [t.alpha for t in material.terms]
        pad = [0.0] * (8 - len(mus))
        return "*MAT_OGDEN_RUBBER_TITLE", [head, mus + pad, alphas + pad, *visco], notes
    if isinstance(material, OgdenHyperfoam):
        nus = {round(t.nu, 12) for t in material.terms}
        if len(material.terms) > 8:
            raise ExportError(f"{name}: LS-DYNA *MAT_OGDEN_RUBBER takes at most 8 terms")
        if len(nus) != 1 or min(nus) < LSDYNA_OGDEN_MIN_NU:
            what = (f"*MAT_OGDEN_RUBBER with PR = {pr:.4f} (the same small-strain shear and bulk "
                    f"moduli, mu0 = {inst_mu:.6g} Pa, K0 = {k_inst:.6g} Pa)")
            message = (f"{name}: ogden_hyperfoam with nu = {sorted(nus)} is a compressible foam; "
                       f"LS-DYNA's *MAT_OGDEN_RUBBER splits off the volume change and matches it "
                       f"only for one nu >= {LSDYNA_OGDEN_MIN_NU}")
            if not approximate:
                raise ExportError(message + f". With --approximate the export writes {what}")
            notes.append(message + f"; written instead: {what}")
        mus = [2.0 * t.mu_pa * long_dev / t.alpha * s for t in material.terms]
        alphas = [t.alpha for t in material.terms]
        pad = [0.0] * (8 - len(mus))
        return "*MAT_OGDEN_RUBBER_TITLE", [head, mus + pad, alphas + pad, *visco], notes
    if isinstance(material, LinearElastic):
        if material.prony:
            raise ExportError(f"{name}: LS-DYNA export of a viscoelastic linear_elastic "
                              "material is not supported")
        e = 9.0 * k_long * mu_long / (3.0 * k_long + mu_long)
        return "*MAT_ELASTIC_TITLE", [[mid, density_kg_m3 * units.density, e * s, pr]], notes
    raise ExportError(f"{name}: material model {material.model!r} has no LS-DYNA card")

