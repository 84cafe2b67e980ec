"""What was read in the published texts behind the chain report's claims (issue 17, items 3 and 6).

Each :class:`Finding` is a sentence read in a stored copy of a paper (the `search` tool's public pages:
often only a page's opening is stored), with the paper, the place in it and the exact wording. The
verdict table (``_study_presets.verdict_table``) prints them beside the report's own numbers; a claim
with no finding says so. ``SEARCHES`` records the look-ups that found **no** text with the papers'
parameters, so that the next search starts elsewhere (docs/chain.md, "Presets").

Rules kept here: a finding is the source's own wording, never a paraphrase from memory; a paper's
account of *another* paper is marked ``secondary`` (it is what that paper says the other found, not the
other's text); a stored copy cut short is marked with ``[…]`` where it stops.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["FINDINGS", "SEARCHES", "Finding", "findings_for"]


@dataclass(frozen=True)
class Finding:
    #: the verdict table's claim this bears on: "vas", "cl", "dsvvn", "mk", "sak"
    claim: str
    source: str
    #: where in the source (section, paragraph, figure) and which stored copy was read
    place: str
    #: the source's own words
    quote: str
    #: True when the source reports what *another* paper found
    secondary: bool = False


FINDINGS = (
    Finding("vas", "Vasconcelos, PRL 76, 4865 (1996)", "text under Fig. 3 (the paper's own text; the seed)",
            "An extrapolation for ν → 0 shows that the transition is indeed discontinuous: Δ = 0.17 at ν_f = 1/2, "
            "whereas Δ = 0 for ν_f > 1/2."),
    Finding("vas", "Vasconcelos, PRL 76, 4865 (1996)", "last paragraph",
            "(homogeneous) spring-block models cannot be brought to a critical state displaying scaling behavior"),
    Finding("cl", "Carlson & Langer, PRA 40, 6470 (1989)",
            "abstract, p. 1 (de.scribd.com/document/250510769/Carlson-Langer-1; the OCR reads 'Csutenberg')",
            "Their size distributions are found numerically to be consistent with the Gutenberg-Richter law."),
    Finding("cl", "J. M. Carlson, J. Geophys. Res. 96 (1991), doi:10.1029/90JB02474 (same homogeneous model)",
            "abstract (earthref.org/ERR/38696)",
            "We find that the model gives rise to slipping events of all sizes; the smaller events are consistent "
            "with the Gutenberg-Richter statistical law, whereas the characteristic events have a separate "
            "statistical distribution."),
    Finding("cl", "B. E. Shaw, J. M. Carlson & J. S. Langer, J. Geophys. Res. 97 (1992), doi:10.1029/91JB01796 (the "
            "same group's mechanical model of a fault; its variant and parameters are not in the abstract)",
            "abstract, second sentence (earthref.org/ERR/39420)",
            "The model generates a statistical distribution of events similar to that observed for a single fault, "
            "with a scaling region consistent with the Gutenberg-Richter law at small and moderate magnitudes, and an "
            "excess of events at large magnitudes."),
    Finding("cl", "Sakaguchi, arXiv nlin/0210057", "Sec. 1 (Introduction), on its refs. [7, 8] (Carlson and Langer); "
            "ar5iv.labs.arxiv.org/html/nlin/0210057",
            "All sizes of stick-slip events are observed and the size distribution exhibits a power law in small "
            "scales, but, great events occur more frequently than is expected from the power law.", secondary=True),
    Finding("cl", "Mori & Kawamura, PRL 94, 058501 (2005) = arXiv cond-mat/0408396",
            "third paragraph, on Carlson, Langer and collaborators (ar5iv; the stored copy stops mid-sentence)",
            "These authors paid particular attention to the magnitude distribution of earthquake events, and "
            "examined its dependence on the friction parameter characterizing the nonlinear stick-slip dynamics of "
            "the model. It was observed that, while smaller events persistently obeyed the GR law, i[…]",
            secondary=True),
    Finding("mk", "Mori & Kawamura, arXiv 0706.1871 (their **two-dimensional** short-range model, not the 1D chain)",
            "abstract (ar5iv.labs.arxiv.org/html/0706.1871)",
            "The model is found to exhibit either a “subcritical”, “supercritical” or “near-critical” behavior, "
            "depending on the values of the model parameters."),
    Finding("mk", "Mori & Kawamura, arXiv 0802.1305 (their **two-dimensional** model with long-range interactions, "
            "not the 1D chain)", "abstract (tomesphere.com/paper/0802.1305)",
            "The magnitude distribution exhibits a ``near-critical'' behavior, i.e., a power-law-like behavior close "
            "to the Gutenberg-Richter law, for a wide parameter range with its B-value, B≃0.55, insensitive to the "
            "model parameters"),
    Finding("mk", "Mori & Kawamura, arXiv 0802.1305 (their 2D long-range model's abstract), on their own "
            "**one-dimensional** models", "abstract, last clause of its magnitude sentence "
            "(scifaro.com/en/abs/simulation-study-of-earthquakes-based-on-the-two-dimensional-burridge-knopoff-model-"
            "with-the-long-range-interaction-0802.1305, v2 2009-11-13; the tomesphere copy above stops before it)",
            "in sharp contrast to that of the 2D short-range model and those of the 1D short-range and long-range "
            "models where such a ``near-critical'' behavior is realized only by fine-tuning the model parameters",
            secondary=True),
    Finding("dsvvn", "Vasconcelos, PRL 76, 4865 (1996)",
            "paragraph after Fig. 3, on its ref. [10] (the reference list is not in the text read; PRE 47, R2221 "
            "(1993) is issue 17's reference)",
            "the transition from stick-slip motion to creep was first observed by de Sousa Vieira, Vasconcelos, and "
            "Nagel [10]. These authors showed that in the region corresponding to stick-slip motion, the system "
            "displays a relaxation-oscillation behavior analogous to a first-order transition. They also observed "
            "that as the parameter ν_f approached the transition value the loading-unloading hysteresis became "
            "less dramatic.", secondary=True),
    Finding("sak", "Sakaguchi, arXiv nlin/0210057", "abstract (ar5iv)",
            "The transition from steady sliding to stick-slip is subcritical in a single block and spring system. "
            "However, we find that the transition is continuous in a long chain of blocks and springs. The size "
            "distribution of stick-slip motions exhibits a power law at the critical point."),
)

#: Look-ups of 2026-11-26 (issue 17) that found no text with these papers' parameters or the findings the
#: verdict table needs: (corpus, query as sent, what came back). Earlier searches: presets.py.
SEARCHES = (
    ("pages", "Mori Kawamura simulation study of spatiotemporal correlations of earthquakes as a stick-slip "
     "frictional instability", "MK 2005 abstract (scilit) and opening (ar5iv cond-mat/0408396): no model section"),
    ("pages", "Statistical physics of fracture, friction and earthquakes Kawamura Hatano Kato Biswas Chakrabarti "
     "Burridge-Knopoff model", "RMP 84, 839 abstract and contents only (arxiv-vanity 1112.0148, it.scribd): "
     "sections III.1.1-III.1.3 not stored"),
    ("pages", "1D BK model with short-range interaction magnitude distribution alpha=1 near-critical characteristic "
     "peak alpha=2,3 sigma=0.01 l=3 nu'=0.01", "nothing on the 1D BK model"),
    ("pages", "Mori Kawamura one-dimensional BK model equation of motion dimensionless friction force "
     "velocity-weakening parameter alpha sigma=0.01 l=3 N=800 periodic boundary conditions",
     "J. Xia's page only (ℓ, α, ν defaults; a b table of his long-range model)"),
    ("pages", "Mori Kawamura Journal of Geophysical Research 2006 one-dimensional Burridge-Knopoff model abstract "
     "frictional parameter magnitude distribution subcritical supercritical",
     "MK JGR 2006: title only (sciencedocbox); MK 2D short-range (arXiv 0706.1871) and 2D long-range "
     "(arXiv 0802.1305) abstracts: other models"),
    ("pages", "Takahiro Mori, Hikaru Kawamura TL;DR one-dimensional Burridge-Knopoff model spatiotemporal "
     "correlations frictional parameter α magnitude distribution",
     "MK continuum limit (arXiv 0807.4588) abstract: no α or magnitude numbers"),
    ("pages", "Carlson Langer Shaw Tang intrinsic properties of a Burridge-Knopoff model of an earthquake fault",
     "CLST 1991 not found; CL PRA 1989 page 1, CLS RMP abstract, Sakaguchi-Morita abstract"),
    ("pages", "Carlson Langer Shaw Tang Physical Review A 44 884 1991 intrinsic properties Burridge-Knopoff "
     "abstract small events localized large events delocalized", "not found"),
    ("pages", "Properties of earthquakes generated by fault dynamics Carlson Langer Physical Review Letters 62 2632 "
     "1989", "not found (Carlson JGR 1991 abstract found: earthref.org/ERR/38696)"),
    ("pages", "Carlson Langer mechanical model of an earthquake fault dimensionless equation of motion U_j'' = "
     "l^2 (U_{j+1} - 2U_j + U_{j-1}) - U_j - phi(2 alpha nu + 2 alpha U_j')",
     "CL PRA 1989 page 1 again (the equations are on later pages, not stored)"),
    ("pages", "Dynamics of spring-block models: tuning to criticality, Physical Review E 47 R2221 1993", "not found"),
    ("pages", "M. de Sousa Vieira, G. L. Vasconcelos, S. R. Nagel 1993 spring-block model", "not found"),
    ("pages", "Sakaguchi Stick-Slip Motion and Phase Transition in a Block-Spring System model equations state "
     "variable theta friction force critical point power law exponent size distribution",
     "abstract and introduction only: no model section, no exponent"),
    ("pages", "Spatiotemporal correlations of the one-dimensional spring-block (Burridge-Knopoff) model of "
     "earthquakes are extensively studied by means of numerical computer simulations. The frictional parameter",
     "MK 2005 abstract, MK 2D and continuum-limit abstracts; no 1D JGR 2006 abstract"),
    ("pages", "thesis Burridge-Knopoff Carlson-Langer model simulation l = 10, alpha = 2.5, sigma = 0.01, nu = 0.01 "
     "magnitude distribution localized events delocalized events", "no thesis or notes quoting the parameters"),
    ("code", "Burridge-Knopoff Mori Kawamura 2005 parameters l=3 sigma=0.01 alpha nu' periodic boundary "
     "simulation", "no reimplementation quoting MK"),
    ("code", "Carlson Langer Shaw Tang 1991 friction phi(v) = (1-sigma)/(1+2 alpha v/(1-sigma)) Burridge Knopoff "
     "chain", "nothing relevant"),
    ("docs", "Carlson Langer Burridge-Knopoff model parameters friction drop sigma alpha ell velocity weakening",
     "nothing relevant"),
    ("find_string", "'Mori and Kawamura', 'Carlson and Langer', 'Carlson-Langer', 'Mogi doughnut'",
     "no quotation of either paper's parameters in stored GitHub files"),
    # a second round (issue 17, helper lscan), new routes: the authors' own later texts, arXiv numbers, reviews
    ("pages", "Mori Kawamura one-dimensional Burridge-Knopoff model equation of motion friction parameter alpha l=3 "
     "nu'=0.01 sigma=0.01", "Xia's page again; Moschetta & Mascia, arXiv 1607.08267 (a later paper comparing with "
     "earlier works: secondary, opening only); MathWorld; no MK text"),
    ("pages", "arXiv cond-mat/0408396 Mori Kawamura spatiotemporal correlations earthquakes stick-slip",
     "MK 2005 abstract (scilit) only; other models (2D BK, OFC, train)"),
    ("pages", "Simulation study of the one-dimensional Burridge-Knopoff model of earthquakes Mori Kawamura "
     "velocity-weakening friction parameter α σ = 0.01 ν' = 0.01 l = 3 N = 800",
     "Kawamura et al.'s rate-and-state 1D papers (arXiv 1605.08659, 1805.07237: another friction law), Xia's page"),
    ("pages", "Mori Kawamura 2006 spatiotemporal correlations of earthquake events in the one-dimensional spring-block "
     "model arXiv physics.geo-ph", "MK JGR 2006 under its title at sciencedocbox: a list of similar documents, "
     "no text; MK 2D (arXiv 0706.1871) abstract"),
    ("pages", "Carlson Langer Shaw Dynamics of earthquake faults Reviews of Modern Physics adap-org/9307001 model "
     "parameters", "CLS RMP 1994 abstract (scec.org/publication/171) only; ar5iv of adap-org/9307001 not stored"),
    ("pages", "ar5iv adap-org/9307001 Dynamics of earthquake faults Carlson Langer Shaw",
     "Langer, Carlson, Myers & Shaw, PNAS 93, 3825 (1996) (nap.edu/read/5709/chapter/18): the same group's 1D "
     "model, but only the abstract and first sentence are stored — no equation or parameter reached"),
    ("pages", "Slip complexity in dynamic models of earthquake faults Langer Carlson Myers Shaw one-dimensional model "
     "equation of motion friction sigma alpha ell nu", "the same PNAS opening (nap.edu) and its SCEC entry "
     "(scec.org/publication/444): abstract only"),
    ("pages", "de Sousa Vieira Vasconcelos Nagel dynamics of spring-block models tuning to criticality",
     "not found (train-model and OFC papers)"),
    ("pages", "ar5iv 1112.0148 Statistical physics of fracture, friction and earthquakes Kawamura Hatano Kato Biswas "
     "Chakrabarti", "RMP 84, 839 (2012): abstract and table of contents again (arxiv-vanity, scribd, scdigest); "
     "section III.1.3 (the 1D BK model with short-range interaction) not stored"),
    ("issues", "Carlson Langer 1989 Burridge-Knopoff chain parameters l=10 alpha=2.5 sigma=0.01 simulation reproduce "
     "magnitude distribution", "nothing on the BK chain (Virtual Quake, SeismoStats threads)"),
    ("docs", "Mori Kawamura PRL 94 058501 one-dimensional Burridge-Knopoff parameters",
     "nothing relevant (other spring-slider codes)"),
    ("docs", "Intrinsic properties of a Burridge-Knopoff model of an earthquake fault Carlson Langer Shaw Tang 1991",
     "nothing relevant"),
    ("code", "Mori Kawamura Burridge-Knopoff 1D model magnitude distribution alpha=1 Gutenberg-Richter alpha=2 "
     "characteristic peak", "student BK projects and seismic-hazard code; no MK parameters"),
    ("find_string", "'0408396' (MK 2005's arXiv number), 'Carlson, Langer, Shaw and Tang', 'PhysRevA.44.884'",
     "no citation of either paper in stored GitHub files (the number only inside unrelated digits)"),
    ("pages", "Takahiro Mori doctoral thesis Osaka University Burridge-Knopoff model earthquakes simulation",
     "no thesis; MK 2D long-range abstract in full at scifaro (arXiv 0802.1305 v2), whose last clause on their 1D "
     "models is now a finding (FINDINGS, 'mk'): words, no parameter"),
    ("pages", "Carlson Langer Shaw Tang 1991 Burridge-Knopoff friction drop sigma one-way slipping zero loading "
     "velocity limit events localized delocalized", "CL PRA 1989 page 1 again; no CLST text"),
    # a third round (issue 17, helper lit3): only page openings came back (also to a query aimed at the model
    # section of a stored ar5iv paper), so the routes were pages whose opening could hold
    # the numbers (figure captions, abstracts of the authors' other papers, slides, APS/earthref/ldeo abstract
    # pages, Japanese pages, arXiv-source and summary sites) and GitHub text (find_string, reimplementations)
    ("pages", "Mori Kawamura 1D BK model dimensionless equation of motion friction force σ frictional parameter α l "
     "periodic boundary conditions N=800", "Xia's page again (with its b table of a long-range model); openings of "
     "other BK papers (train model, traveling waves, de Sousa Vieira & Herrmann chao-dyn/9312004, Moschetta & "
     "Mascia); no MK text"),
    ("pages", "ar5iv cond-mat/0408396 the dimensionless equation of motion of the i-th block, ℓ, ν, friction force φ, "
     "σ drop, 2α", "friction papers of other fields; MK's model section not reached"),
    ("pages", "two-dimensional BK model equation of motion in dimensionless form, friction force φ, we fix σ and ν' in "
     "our simulations, periodic boundary conditions, L×L blocks", "a test whether text past a stored page's opening "
     "can be matched (MK's 2D paper, arXiv 0706.1871): no such passage came back; every hit is a page opening"),
    ("pages", "Mogi doughnut quiescence Burridge-Knopoff simulation parameters α = 1 σ = 0.01 ℓ = 3 ν = 0.01 N = 800 "
     "periodic", "Moschetta & Mascia openings, MK continuum-limit abstract (arxivlens), Hasumi 2D; no number"),
    ("pages", "Predictor-Corrector Burridge-Knopoff simulations parameters chosen as in Carlson Langer, ℓ^2, α, σ, ν "
     "values Gutenberg-Richter histogram", "Moschetta & Mascia opening only (their comparison section not stored)"),
    ("docs", "Mori Kawamura one-dimensional Burridge-Knopoff model arXiv", "other spring-slider codes "
     "(statmechcode/2L-model, EQcycle_polylinear); nothing on MK"),
    ("pages", "latex-in-arxiv cond-mat0408396 Mori Kawamura \\documentclass Burridge-Knopoff",
     "LaTeX manuals; MK's source not stored on latex-in-arxiv.com"),
    ("pages", "\\title{Simulation study of spatiotemporal correlations of earthquakes as a stick-slip frictional "
     "instability} \\author{Takahiro Mori and Hikaru Kawamura}", "MK 2005 abstract (scilit) and ar5iv opening "
     "(stops in the same third paragraph), MK 2D, Kawamura et al. arXiv 1805.07237"),
    ("pages", "Simulation study of the one-dimensional Burridge-Knopoff model of earthquakes Mori Kawamura abstract",
     "MK JGR 2006: the sciencedocbox title page again; no abstract, no arXiv number; Kawamura et al. rate-and-state "
     "papers (arXiv 1605.08659)"),
    ("pages", "physics/0504218 Mori Kawamura", "a guessed arXiv number for MK JGR 2006, used only as a search key: "
     "nothing related"),
    ("pages", "Mori Kawamura 2006 one-dimensional BK model magnitude distribution depends on frictional parameter α; "
     "α=1 near-critical Gutenberg-Richter, larger α characteristic peak, subcritical supercritical abstract JGR",
     "the same MK titles and abstracts; Sornette's 1992 mean-field model"),
    ("pages", "Figure 1 from Simulation study of spatiotemporal correlations of earthquakes as a stick-slip "
     "frictional instability magnitude distribution caption", "no figure page of MK stored (scilit abstract only)"),
    ("pages", "figure caption magnitude distribution of the one-dimensional BK model for various values of the "
     "frictional parameter α, σ=0.01, ℓ=3", "Xia's page; Kawamura et al. rate-and-state abstracts; no caption"),
    ("pages", "Statistical physics of fracture, friction, and earthquakes Rev. Mod. Phys. 84 839 one-dimensional BK "
     "model magnitude distribution figure caption α σ ν", "RMP 2012: abstract and contents again (arxiv-vanity, "
     "it.scribd 'page 1 of 52', scdigest); Sec. III.1.3 not stored"),
    ("pages", "researchgate publication Simulation study of spatiotemporal correlations of earthquakes as a "
     "stick-slip frictional instability Mori Kawamura figures", "no ResearchGate page; the same MK openings"),
    ("pages", "arxiver Takahiro Mori Hikaru Kawamura spatiotemporal correlations one-dimensional spring-block model "
     "earthquakes frictional parameter α Mogi doughnut arXiv:physics", "the same MK openings; no JGR 2006"),
    ("pages", "ar5iv 0807.4588 continuum limit one-dimensional Burridge-Knopoff model introduction previous studies "
     "discrete BK model frictional parameter", "MK continuum limit: abstract only (tomesphere); no ar5iv opening"),
    ("pages", "Mori Kawamura 2D long-range interaction Burridge-Knopoff introduction our previous study of the 1D "
     "model near-critical fine-tuning α", "the 0802.1305 abstract again (tomesphere, scifaro, and koineu.com with "
     "a machine-written summary: not the paper's text); no 1D number"),
    ("pages", "koineu posts Mori Kawamura one-dimensional Burridge-Knopoff spatio-temporal correlations stick-slip "
     "frictional instability research summary", "no such post for MK's 1D papers"),
    ("pages", "slides Kawamura statistical physics of earthquakes Burridge-Knopoff model 1D magnitude distribution "
     "α=1 α=2 α=3 σ ℓ ν' lecture", "no slides; Hasumi 2D abstracts, de Sousa Vieira cond-mat/9602108 abstract"),
    ("pages", "バネ-ブロック Burridge-Knopoff モデル 河村 森 1次元 摩擦パラメータ α マグニチュード分布 シミュレーション",
     "Japanese pages: Kawamura's KAKEN report 2010 (2D BK, rate-and-state), Sakaguchi's JpGU 2019 abstract; no "
     "parameter"),
    ("pages", "Results for the 1D BK model with zero loading velocity sigma drop one direction Xia EQProject",
     "only Xia's BK1D page; its linked sub-pages are not stored (σ's value still not read)"),
    ("pages", "Carlson Langer 1989 uniform chain of blocks and springs velocity-weakening friction slipping events "
     "localized delocalized Gutenberg-Richter abstract Physical Review Letters", "CL PRA 1989 page 1 (scribd) "
     "again; no PRL 62, 2632 page"),
    ("pages", "scribd Carlson Langer mechanical model of an earthquake fault II. THE MODEL dimensionless variables "
     "equation of motion friction function φ α parameter", "scribd stores page 1 of 15 only ('Sie sind auf Seite 1 "
     "von 15'); Shaw 1997 abstract (ldeo.columbia.edu), SCEC entries"),
    ("pages", "journals.aps.org pra abstract 10.1103/PhysRevA.44.884 Carlson Langer Shaw Tang", "nothing (no APS "
     "abstract page of CLST stored)"),
    ("pages", "ldeo.columbia.edu shaw abstracts Intrinsic properties of a Burridge-Knopoff model of an earthquake "
     "fault Carlson Langer Shaw Tang 1991", "no CLST abstract; arxiver lists CLS RMP (adap-org/9307001) and Pepke, "
     "Carlson & Shaw (chao-dyn/9307019) abstracts: no parameter"),
    ("pages", "Shaw Carlson Langer 1992 patterns of seismic activity preceding large earthquakes one-dimensional "
     "uniform model abstract", "found: Shaw, Carlson & Langer, JGR 97 (1992) abstract (earthref.org/ERR/39420), now "
     "a finding (FINDINGS, 'cl'): words, no parameter"),
    ("pages", "earthref Carlson Langer Shaw mechanical model fault friction parameter abstract JGR Burridge-Knopoff",
     "CL PRA page 1, CLS RMP and LCMS PNAS SCEC entries again; no parameter"),
    ("pages", "Carlson Langer model stiffness parameter l = 10, velocity-weakening α = 2.5, σ = 0.01, ν = 0.01 as in "
     "Carlson et al. we use the same parameters", "Xia's page; Sakaguchi & Morita (arXiv 1309.4583) introduction: "
     "'Carlson et al. used a type of velocity-weakening friction and observed a power law in the range of small "
     "magnitude' (secondary, no number)"),
    ("pages", "de Sousa Vieira Vasconcelos Nagel spring-block chain transition stick-slip to creep first-order "
     "hysteresis ν_f Physical Review E 1993", "not found; the seed's own abstract (concepedia) and Sakaguchi's "
     "introduction"),
    ("pages", "de Sousa Vieira exponential distributions mechanical model earthquakes Burridge-Knopoff equations of "
     "motion friction ν_f parameter", "de Sousa Vieira's cond-mat/9602108 abstract (tomesphere): no dSVVN number"),
    ("pages", "de Sousa Vieira chaos and synchronized chaos in an earthquake model two blocks friction law",
     "her cond-mat/9312072 abstract and two-block papers of others; nothing of PRE 47, R2221"),
    ("code", "thesis LaTeX Burridge-Knopoff chain Carlson Langer friction \\phi(\\dot U) = (1-\\sigma)/(1 + 2\\alpha "
     "\\dot U/(1-\\sigma)) \\ell^2 \\nu", "no thesis source; rate-and-state codes"),
    ("code", "Burridge-Knopoff simulation Mori Kawamura parameters l = 3, sigma = 0.01, nu = 0.01 periodic boundary "
     "800 blocks magnitude distribution alpha", "student BK projects; no MK parameters"),
    ("docs", "Burridge-Knopoff model Python package velocity-weakening friction Carlson-Langer parameters "
     "documentation", "no BK package; rate-and-state toolkits (rsfmodel)"),
    ("find_repos", "'knopoff', 'burridge', 'spring-block' (then read_file of the READMEs of bokhylle/"
     "1dBurridgeKnopoffMatlab and PrincepsNumerorum/Burridge-Knopoff-1D-Simulator)", "reimplementations "
     "(larashores/burridgeknopoffsimulator, alireza-astane/Burridge_Knopoff_Model, chunhuizhao478/"
     "Spring-Block-Model, the two above): none quotes CL, CLST or MK parameters"),
    ("find_string", "'PhysRevLett.94.058501', 'PhysRevA.40.6470', 'Burridge-Knopoff', 'BK model with short-range "
     "interaction', 'Mori and Kawamura, 2006', 'sigma=0.01, nu'", "0, 0, 10 unrelated, 0, 0, 10 unrelated hits"),
    ("find_string", "'Carlson et al. (1991)', 'Carlson & Langer', 'Mori & Kawamura'", "1 unrelated; 7 and 2 hits in "
     "reimplementations' notes (an AI-written CL reproduction; a pore-pressure BK code citing 'Mori & Kawamura "
     "(2006, 2008)' for validation): no value attributed to the papers' text"),
)


def findings_for(claim: str) -> tuple:
    return tuple(f for f in FINDINGS if f.claim == claim)
