"""Published parameter sets of Burridge–Knopoff chains as named presets (issue 17, item 3).

`bifurcation chain --preset NAME`, ``bifurcation.chain(..., preset=NAME)`` and a workflow's
``[model] preset = "NAME"`` fill every chain parameter the user does not give. Each number says where
it was read (``Preset.provenance``); a number that could not be read in a source says so, and the
preset is then marked ``verified = False``: a reproduction built on it is a reproduction of the
parameters as stated here, not of the paper.

Mapping onto this project's variables (docs/chain.md, "Presets"): σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j
+ νt and friction Φ(V/ν_f). Carlson and Langer write the velocity-weakening friction with a parameter α
as φ(2αV) with slope −2α at V → 0⁺ (with the drop σ, φ_σ(V) = (1 − σ)/(1 + 2αV/(1 − σ)), the form this
project implements as Φ_σ, docs/chain.md "Friction drop"), so x = V/ν_f = 2αV and **ν_f = 1/(2α)**; ℓ,
ν and σ are the same dimensionless numbers in both. (The correspondence of the variables is the one
docs/chain.md states for the model; it was not re-derived here from CLST's own text, which could not
be read, see below.)
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ...errors import InputError

__all__ = ["PRESETS", "Preset", "get_preset", "preset_names", "workflow_preset"]

#: Sources read for these presets with the `search` tool (stored public pages; issue 17, item 3).
#: Only what these pages show was used; a number that none of them shows is marked NOT READ.
XIA = "J. Xia, 'Results for 1D BK model', physics.clarku.edu/~jcxia/EQProject/BK1D.html (2005)"
XIA_CUT = "J. Xia, velocity-cutoff page, physics.clarku.edu/~jcxia/EQProject/evnt_vcutoff.html"
SEED = "Vasconcelos, PRL 76, 4865 (1996)"
#: Carlson & Langer, PRA 40, 6470 (1989), first page and abstract (de.scribd.com/document/250510769/Carlson-Langer-1):
#: a uniform chain, inertia kept, no imposed noise or inhomogeneity, velocity-weakening stick-slip friction,
#: "size distributions ... consistent with the Gutenberg-Richter law". Its parameter values were not on that page.
CL_PRA = "Carlson & Langer, PRA 40, 6470 (1989), p. 1 (abstract), de.scribd.com/document/250510769/Carlson-Langer-1"
#: Mori & Kawamura, PRL 94, 058501 (2005) = arXiv cond-mat/0408396, opening (ar5iv.labs.arxiv.org/html/cond-mat/0408396):
#: the 1D spring-block (BK) model; the parameter section was not reachable (the stored page gives its first part only).
MK_PRL = "Mori & Kawamura, PRL 94, 058501 (2005), arXiv cond-mat/0408396 (opening only, ar5iv)"
#: Searched and NOT found as text: CL PRL 62, 2632 (1989); CLST PRA 44, 884 (1991); CLS RMP 66, 657 (1994)
#: beyond its abstract (scec.org/publication/171, arXiv adap-org/9307001); MK JGR 111, B07302 (2006) beyond
#: its title; de Sousa Vieira, Vasconcelos & Nagel, PRE 47, R2221 (1993): nothing.
#: Searched again for issue 17 (pages and docs corpora; only each page's opening is returned): Kawamura,
#: Hatano, Kato, Biswas & Chakrabarti, RMP 84, 839 (2012) = arXiv:1112.0148 (arxiv-vanity, scribd): abstract
#: and contents only (its sections III.1.1-III.1.3 on the 1D BK model were not reached); MK JGR 2006
#: (sciencedocbox): title only; MK 2D, arXiv:0706.1871 (ar5iv): abstract and introduction only; Weatherley &
#: Abe, NPG 11, 553 (2004) (123dok), "a reproduction of the Block-Slider model of Carlson et al. (1991)":
#: title page and abstract only; CLST 1991, de Sousa Vieira-Vasconcelos-Nagel 1993: not found. So every
#: NOT READ below stays so. Searched once more on 2026-11-26 (pages corpus: de Sousa Vieira-Vasconcelos-Nagel
#: 1993; MK 2005 parameters; CLST 1991): no new text found (hits were other BK/train-model papers).
#: And again for issue 17 (19 look-ups over the pages, code and docs corpora and find_string, each listed
#: in literature.SEARCHES): no parameter found; the findings read in words are in literature.FINDINGS.
#: A second round (16 look-ups, new routes: the authors' own later texts such as Langer, Carlson, Myers & Shaw,
#: PNAS 93, 3825 (1996), arXiv numbers, the RMP 2012 review, the issues corpus; literature.SEARCHES from the
#: 20th on): only openings and abstracts again, no parameter (one clause of MK on their 1D models, in words,
#: became a finding: literature.FINDINGS); every NOT READ below stays so.
#: A third round (helper lit3; literature.SEARCHES entries 36-73, some bundling several look-ups): only page openings came
#: back (also to a query aimed at the model section of a stored ar5iv paper), so pages whose opening could
#: hold the numbers were tried (figure captions, the authors' other abstracts, APS/earthref/ldeo abstract pages,
#: slides, Japanese pages, the scribd copy of CL PRA 1989 beyond page 1, Xia's sub-pages) and GitHub text
#: (reimplementations, find_string for DOIs and citations). One finding in words (Shaw, Carlson & Langer, JGR 97
#: (1992), abstract: literature.FINDINGS), no parameter: no value below changes and every NOT READ stays so.


@dataclass(frozen=True)
class Preset:
    name: str
    title: str
    law: str
    n: int
    ell: float
    nu: float
    nu_f: float
    sigma: float
    ends: str
    #: per parameter: where its value was read, or why it could not be
    provenance: dict = field(default_factory=dict)
    #: every number read in a source (False: some are not, see provenance)
    verified: bool = False
    note: str = ""

    def parameters(self) -> dict:
        return {"law": self.law, "n": self.n, "ell": self.ell, "nu": self.nu, "nu_f": self.nu_f,
                "sigma": self.sigma, "ends": self.ends}


PRESETS = {p.name: p for p in (
    Preset(
        name="vasconcelos-1996",
        title="The seed's own model: one block, Carlson–Langer friction, no drop, slow driving",
        law="carlson-langer", n=1, ell=0.0, nu=1e-9, nu_f=0.5, sigma=0.0, ends="free",
        provenance={
            "law": f"{SEED}, Eq. (19): Φ(x) = 1/(1 + x) (the Carlson–Langer law of Fig. 3)",
            "n": f"{SEED}: the paper's model is a single block (Eqs. (1)-(5)); chains are discussed, not run",
            "ell": "not in the paper (one block: ℓ plays no part)",
            "nu": f"{SEED}, text of Fig. 3: 'Δ was computed numerically for ν = 10^-9'",
            "nu_f": f"{SEED}: the transition at ν_f = 1/2 (text after Eq. (18) and Fig. 2)",
            "sigma": f"{SEED}, Eqs. (2)-(3): Φ(0) = 1, Φ'(0) = −1, no static-to-dynamic drop",
        },
        verified=True,
        note="N = 1 is exactly the paper's block; ν_f = 1/2 is the point of its transition, so sweep ν_f "
             "around it (docs/physics.md)"),
    Preset(
        name="carlson-langer-1991",
        title="Carlson–Langer chain with a friction drop (Carlson, Langer, Shaw, Tang, PRA 44, 884 (1991))",
        law="carlson-langer", n=1000, ell=10.0, nu=0.01, nu_f=0.2, sigma=0.01, ends="free",
        provenance={
            "law": f"{SEED}, Eq. (19) names Φ = 1/(1 + x) the Carlson–Langer law; {CL_PRA}: velocity-weakening "
                   "stick-slip friction (its formula and the meaning of α, x = 2αV, NOT READ in CL or CLST)",
            "ell": f"{XIA}: 'The default values we used for these three parameters [ℓ, α, ν] are 10, 2.5, and "
                   "0.01' (a reimplementation, not CLST's text; NOT READ in CLST)",
            "nu": f"{XIA} (as ell); NOT READ in CLST",
            "nu_f": f"α = 2.5 from {XIA}; ν_f = 1/(2α) = 0.2 by the mapping in this module's docstring (NOT READ in CLST)",
            "sigma": f"NOT READ: {XIA} says a drop σ was used 'as they did (1991 PRA)' without its value; "
                     "0.01 is the value issue 17 quotes",
            "n": f"NOT READ in CLST; {XIA} tabulates N = 1000 and 5000; 1000 taken",
            "ends": "NOT READ: free ends assumed",
        },
        note="CLST also study the ν → 0 limit (Xia: 'moving only in one direction at the zero-loading velocity "
             "limit'); this engine runs at the finite ν given. Xia's velocity cutoff for event membership is "
             f"0.01 at ν = 0.01 ({XIA_CUT}), in a model whose drive is frozen during events"),
    Preset(
        name="mori-kawamura-2006",
        title="Mori & Kawamura's one-dimensional chain (PRL 94, 058501 (2005); JGR 111, B07302 (2006))",
        law="carlson-langer", n=800, ell=3.0, nu=0.01, nu_f=0.25, sigma=0.01, ends="periodic",
        provenance={
            "law": f"NOT READ: {MK_PRL} names the 1D BK model and CL's friction parameter, not the formula; "
                   "the Carlson–Langer form with a drop is the issue's (17) summary",
            "n": "NOT READ: N = 800 is the issue's (17) summary ('commonly cited as'), not read in MK",
            "ends": "NOT READ: periodic, the issue's (17) summary",
            "ell": "NOT READ: ℓ = 3, the issue's (17) summary",
            "nu": "NOT READ: ν ≈ 0.01, the issue's (17) summary",
            "sigma": "NOT READ: σ = 0.01, the issue's (17) summary",
            "nu_f": "NOT READ: α = 1 … 3 in the issue's summary (ν_f = 1/2 … 1/6); α = 2 (ν_f = 0.25) taken, the "
                    "characteristic-peak side of MK's claim as the issue states it",
        },
        note="every number unverified (searched: MK 2005's opening only, MK 2006's title only): a run on it "
             "reproduces the issue's summary of MK, not MK"),
)}


def preset_names() -> list[str]:
    return sorted(PRESETS)


def get_preset(name) -> Preset:
    """The preset ``name``; a one-line error naming the known ones otherwise."""
    if not isinstance(name, str) or name not in PRESETS:
        raise InputError("preset", name, "is not a known preset", f"use one of {', '.join(preset_names())}")
    return PRESETS[name]


def workflow_preset(name) -> tuple[dict, tuple]:
    """The chain's ``presets`` hook: a workflow's ``[model] preset`` as (axis values, (label,))."""
    p = get_preset(name)
    points = {"n": p.n, "ell": p.ell, "nu": p.nu, "nu_f": p.nu_f, "sigma": p.sigma,
              "periodic": int(p.ends == "periodic")}
    return points, ([p.law],)
