"""ISO 286-1/-2:2010 limits and fits: standard tolerances, fundamental deviations, fits.

The standard is kept here as data, transcribed from ISO 286-1:2010 (GPS — ISO code system for
tolerances on linear sizes — Part 1: Basis of tolerances, deviations and fits):

* Table 1 — standard tolerance grades IT1 … IT18, nominal sizes up to 3150 mm;
* Annex A, Table A.1 — grades IT01 and IT0, nominal sizes up to 500 mm;
* Table 2 — fundamental deviations of holes A … M (J values; footnotes on JS and M6);
* Table 3 — fundamental deviations of holes N … ZC and the Δ values;
* Table 4 — fundamental deviations of shafts a … j;
* Table 5 — fundamental deviations of shafts k … zc.

ISO 286-2:2010 tabulates limit deviations of the commonly used classes *computed* from these
tables; the lookup code below applies the same rules generically:

* shafts a … h: upper deviation ``es`` from Table 4, ``ei = es − IT``;
* shafts j, k … zc: lower deviation ``ei`` from Tables 4 and 5, ``es = ei + IT``;
* js / JS: ``±IT/2``; for grades 7 to 11 an odd IT value in µm is first rounded down to the
  even value below (footnote to Tables 2 and 4), so that the deviations are whole µm;
* holes A … H: ``EI = −es`` of the shaft with the same letter, ``ES = EI + IT``;
* holes J: ``ES`` from Table 2, ``EI = ES − IT``;
* holes K, M, N up to IT8 and P … ZC up to IT7, for sizes over 3 up to 500 mm:
  ``ES = −ei + Δ`` with ``Δ = ITn − IT(n−1)`` from Table 3; above those grades (and for sizes
  up to 3 mm and above 500 mm) ``ES = −ei``, except K above IT8 (defined only up to 3 mm,
  ``ES = 0``) and N above IT8 over 3 up to 500 mm (``ES = 0``); K uses the k value of the
  IT4 … IT7 column for every grade up to IT8 (Table 2 writes it "−k + Δ");
* grades below IT3 (IT01 … IT2) have no Δ in Table 3, so K, M, N and P … ZC in those grades
  are only defined where no Δ is needed (up to 3 mm and above 500 mm);
* not used: A, B, a, b and N above IT8 up to 1 mm; IT14 … IT18 up to 1 mm (notes to
  Tables 1 to 4); J only as J6, J7, J8 and j only as j5, j6, j7 (up to 500 mm) and j8 (up to
  3 mm); CD, EF, FG are tabulated only up to 10 mm; T, V, Y start over 24, 14 and 18 mm;
  A, B, C, V … ZC (and lower case) end at 500 mm;
* special case (Table 2): M6 over 250 up to 315 mm has ``ES = −9 µm`` instead of −11 µm.

A size exactly on a boundary belongs to the lower range ("over 6 up to and including 10").
Sizes are SI (metres) at the API; deviations are stored in metres and also offered in
micrometres, the unit the standard uses.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal, TypeVar

from jointplay.errors import StandardsError

__all__ = [
    "GRADES",
    "HOLE_LETTERS",
    "SHAFT_LETTERS",
    "Fit",
    "ToleranceClass",
    "class_as_dict_um",
    "fit",
    "parse_designation",
    "size_range_mm",
    "standard_tolerance",
    "tolerance_class",
]

_T = TypeVar("_T")
Kind = Literal["hole", "shaft"]
FitType = Literal["clearance", "transition", "interference"]

#: A column of one of the standard's tables: rows ``(upper limit of the nominal size range in
#: mm, value in µm)``. A row covers "over the previous upper limit up to and including this
#: one"; the first row starts above 0 mm. ``None`` marks a cell the standard leaves empty.
Column = tuple[tuple[float, float | None], ...]

#: Standard tolerance grades in ISO 286-1 order.
GRADES: tuple[str, ...] = ("01", "0", *(str(n) for n in range(1, 19)))

#: Largest nominal size covered by ISO 286-1:2010, mm.
MAX_SIZE_MM = 3150.0

# ---------------------------------------------------------------------------------------------
# ISO 286-1:2010 Table 1 — standard tolerance values IT1 … IT18, µm (the standard prints
# IT12 … IT18 in mm; they are given here in µm). Note to Table 1: IT14 … IT18 shall not be
# used for nominal sizes up to and including 1 mm.
# ---------------------------------------------------------------------------------------------
#: ``(upper limit mm, (IT1, IT2, …, IT18) in µm)``.
STANDARD_TOLERANCES_UM: tuple[tuple[float, tuple[float, ...]], ...] = (
    # up to mm  IT1  IT2   IT3  IT4  IT5  IT6  IT7  IT8  IT9 IT10  IT11  IT12  IT13  IT14  IT15   IT16   IT17   IT18
    (3, (0.8, 1.2, 2, 3, 4, 6, 10, 14, 25, 40, 60, 100, 140, 250, 400, 600, 1000, 1400)),
    (6, (1, 1.5, 2.5, 4, 5, 8, 12, 18, 30, 48, 75, 120, 180, 300, 480, 750, 1200, 1800)),
    (10, (1, 1.5, 2.5, 4, 6, 9, 15, 22, 36, 58, 90, 150, 220, 360, 580, 900, 1500, 2200)),
    (18, (1.2, 2, 3, 5, 8, 11, 18, 27, 43, 70, 110, 180, 270, 430, 700, 1100, 1800, 2700)),
    (30, (1.5, 2.5, 4, 6, 9, 13, 21, 33, 52, 84, 130, 210, 330, 520, 840, 1300, 2100, 3300)),
    (50, (1.5, 2.5, 4, 7, 11, 16, 25, 39, 62, 100, 160, 250, 390, 620, 1000, 1600, 2500, 3900)),
    (80, (2, 3, 5, 8, 13, 19, 30, 46, 74, 120, 190, 300, 460, 740, 1200, 1900, 3000, 4600)),
    (120, (2.5, 4, 6, 10, 15, 22, 35, 54, 87, 140, 220, 350, 540, 870, 1400, 2200, 3500, 5400)),
    (180, (3.5, 5, 8, 12, 18, 25, 40, 63, 100, 160, 250, 400, 630, 1000, 1600, 2500, 4000, 6300)),
    (250, (4.5, 7, 10, 14, 20, 29, 46, 72, 115, 185, 290, 460, 720, 1150, 1850, 2900, 4600, 7200)),
    (315, (6, 8, 12, 16, 23, 32, 52, 81, 130, 210, 320, 520, 810, 1300, 2100, 3200, 5200, 8100)),
    (400, (7, 9, 13, 18, 25, 36, 57, 89, 140, 230, 360, 570, 890, 1400, 2300, 3600, 5700, 8900)),
    (500, (8, 10, 15, 20, 27, 40, 63, 97, 155, 250, 400, 630, 970, 1550, 2500, 4000, 6300, 9700)),
    (630, (9, 11, 16, 22, 32, 44, 70, 110, 175, 280, 440, 700, 1100, 1750, 2800, 4400, 7000, 11000)),
    (800, (10, 13, 18, 25, 36, 50, 80, 125, 200, 320, 500, 800, 1250, 2000, 3200, 5000, 8000, 12500)),
    (1000, (11, 15, 21, 28, 40, 56, 90, 140, 230, 360, 560, 900, 1400, 2300, 3600, 5600, 9000, 14000)),
    (1250, (13, 18, 24, 33, 47, 66, 105, 165, 260, 420, 660, 1050, 1650, 2600, 4200, 6600, 10500, 16500)),
    (1600, (15, 21, 29, 39, 55, 78, 125, 195, 310, 500, 780, 1250, 1950, 3100, 5000, 7800, 12500, 19500)),
    (2000, (18, 25, 35, 46, 65, 92, 150, 230, 370, 600, 920, 1500, 2300, 3700, 6000, 9200, 15000, 23000)),
    (2500, (22, 30, 41, 55, 78, 110, 175, 280, 440, 700, 1100, 1750, 2800, 4400, 7000, 11000, 17500, 28000)),
    (3150, (26, 36, 50, 68, 96, 135, 210, 330, 540, 860, 1350, 2100, 3300, 5400, 8600, 13500, 21000, 33000)),
)  # fmt: skip

#: ISO 286-1:2010 Annex A, Table A.1 — IT01 and IT0 in µm, tabulated up to 500 mm only.
STANDARD_TOLERANCES_IT01_IT0_UM: tuple[tuple[float, tuple[float, float]], ...] = (
    (3, (0.3, 0.5)),
    (6, (0.4, 0.6)),
    (10, (0.4, 0.6)),
    (18, (0.5, 0.8)),
    (30, (0.6, 1)),
    (50, (0.6, 1)),
    (80, (0.8, 1.2)),
    (120, (1, 1.5)),
    (180, (1.2, 2)),
    (250, (2, 3)),
    (315, (2.5, 4)),
    (400, (3, 5)),
    (500, (4, 6)),
)

# ---------------------------------------------------------------------------------------------
# ISO 286-1:2010 Table 4 — upper fundamental deviations es of shafts a … h, µm (all grades).
# Footnote: a and b shall not be used for nominal sizes up to 1 mm. CD/EF/FG (cd/ef/fg) are
# tabulated up to 10 mm only (intended mainly for precision mechanics and watchmaking).
# ---------------------------------------------------------------------------------------------
SHAFT_UPPER_DEVIATIONS_UM: Mapping[str, Column] = MappingProxyType({
    "a": ((3, -270), (6, -270), (10, -280), (18, -290), (30, -300), (40, -310), (50, -320),
          (65, -340), (80, -360), (100, -380), (120, -410), (140, -460), (160, -520), (180, -580),
          (200, -660), (225, -740), (250, -820), (280, -920), (315, -1050), (355, -1200),
          (400, -1350), (450, -1500), (500, -1650)),
    "b": ((3, -140), (6, -140), (10, -150), (18, -150), (30, -160), (40, -170), (50, -180),
          (65, -190), (80, -200), (100, -220), (120, -240), (140, -260), (160, -280), (180, -310),
          (200, -340), (225, -380), (250, -420), (280, -480), (315, -540), (355, -600),
          (400, -680), (450, -760), (500, -840)),
    "c": ((3, -60), (6, -70), (10, -80), (18, -95), (30, -110), (40, -120), (50, -130),
          (65, -140), (80, -150), (100, -170), (120, -180), (140, -200), (160, -210), (180, -230),
          (200, -240), (225, -260), (250, -280), (280, -300), (315, -330), (355, -360),
          (400, -400), (450, -440), (500, -480)),
    "cd": ((3, -34), (6, -46), (10, -56)),
    "d": ((3, -20), (6, -30), (10, -40), (18, -50), (30, -65), (50, -80), (80, -100), (120, -120),
          (180, -145), (250, -170), (315, -190), (400, -210), (500, -230), (630, -260),
          (800, -290), (1000, -320), (1250, -350), (1600, -390), (2000, -430), (2500, -480),
          (3150, -520)),
    "e": ((3, -14), (6, -20), (10, -25), (18, -32), (30, -40), (50, -50), (80, -60), (120, -72),
          (180, -85), (250, -100), (315, -110), (400, -125), (500, -135), (630, -145),
          (800, -160), (1000, -170), (1250, -195), (1600, -220), (2000, -240), (2500, -260),
          (3150, -290)),
    "ef": ((3, -10), (6, -14), (10, -18)),
    "f": ((3, -6), (6, -10), (10, -13), (18, -16), (30, -20), (50, -25), (80, -30), (120, -36),
          (180, -43), (250, -50), (315, -56), (400, -62), (500, -68), (630, -76), (800, -80),
          (1000, -86), (1250, -98), (1600, -110), (2000, -120), (2500, -130), (3150, -145)),
    "fg": ((3, -4), (6, -6), (10, -8)),
    "g": ((3, -2), (6, -4), (10, -5), (18, -6), (30, -7), (50, -9), (80, -10), (120, -12),
          (180, -14), (250, -15), (315, -17), (400, -18), (500, -20), (630, -22), (800, -24),
          (1000, -26), (1250, -28), (1600, -30), (2000, -32), (2500, -34), (3150, -38)),
    "h": ((3150, 0),),
})  # fmt: skip

# ISO 286-1:2010 Table 4 — lower fundamental deviations ei of shafts j, µm, by grade. The
# standard has one column for IT5 and IT6, one for IT7 and one for IT8 (up to 3 mm only);
# j is not defined above 500 mm nor for other grades.
_J_IT5_IT6: Column = ((3, -2), (6, -2), (10, -2), (18, -3), (30, -4), (50, -5), (80, -7),
                      (120, -9), (180, -11), (250, -13), (315, -16), (400, -18), (500, -20))  # fmt: skip
_J_IT7: Column = ((3, -4), (6, -4), (10, -5), (18, -6), (30, -8), (50, -10), (80, -12), (120, -15),
                  (180, -18), (250, -21), (315, -26), (400, -28), (500, -32))  # fmt: skip
SHAFT_J_LOWER_DEVIATIONS_UM: Mapping[str, Column] = MappingProxyType(
    {"5": _J_IT5_IT6, "6": _J_IT5_IT6, "7": _J_IT7, "8": ((3, -6),)}
)

#: ISO 286-1:2010 Table 5 — ei of shaft k for grades IT4 to IT7, µm; for grades up to IT3 and
#: above IT7 (and for every grade above 500 mm) ei = 0.
SHAFT_K_IT4_TO_IT7_UM: Column = (
    (3, 0), (6, 1), (10, 1), (18, 1), (30, 2), (50, 2), (80, 2), (120, 3), (180, 3), (250, 4),
    (315, 4), (400, 4), (500, 5), (3150, 0),
)  # fmt: skip

# ---------------------------------------------------------------------------------------------
# ISO 286-1:2010 Table 5 — lower fundamental deviations ei of shafts m … zc, µm (all grades).
# ---------------------------------------------------------------------------------------------
SHAFT_LOWER_DEVIATIONS_UM: Mapping[str, Column] = MappingProxyType({
    "m": ((3, 2), (6, 4), (10, 6), (18, 7), (30, 8), (50, 9), (80, 11), (120, 13), (180, 15),
          (250, 17), (315, 20), (400, 21), (500, 23), (630, 26), (800, 30), (1000, 34),
          (1250, 40), (1600, 48), (2000, 58), (2500, 68), (3150, 76)),
    "n": ((3, 4), (6, 8), (10, 10), (18, 12), (30, 15), (50, 17), (80, 20), (120, 23), (180, 27),
          (250, 31), (315, 34), (400, 37), (500, 40), (630, 44), (800, 50), (1000, 56),
          (1250, 66), (1600, 78), (2000, 92), (2500, 110), (3150, 135)),
    "p": ((3, 6), (6, 12), (10, 15), (18, 18), (30, 22), (50, 26), (80, 32), (120, 37), (180, 43),
          (250, 50), (315, 56), (400, 62), (500, 68), (630, 78), (800, 88), (1000, 100),
          (1250, 120), (1600, 140), (2000, 170), (2500, 195), (3150, 240)),
    "r": ((3, 10), (6, 15), (10, 19), (18, 23), (30, 28), (50, 34), (65, 41), (80, 43), (100, 51),
          (120, 54), (140, 63), (160, 65), (180, 68), (200, 77), (225, 80), (250, 84), (280, 94),
          (315, 98), (355, 108), (400, 114), (450, 126), (500, 132), (560, 150), (630, 155),
          (710, 175), (800, 185), (900, 210), (1000, 220), (1120, 250), (1250, 260), (1400, 300),
          (1600, 330), (1800, 370), (2000, 400), (2240, 440), (2500, 460), (2800, 550),
          (3150, 580)),
    "s": ((3, 14), (6, 19), (10, 23), (18, 28), (30, 35), (50, 43), (65, 53), (80, 59), (100, 71),
          (120, 79), (140, 92), (160, 100), (180, 108), (200, 122), (225, 130), (250, 140),
          (280, 158), (315, 170), (355, 190), (400, 208), (450, 232), (500, 252), (560, 280),
          (630, 310), (710, 340), (800, 380), (900, 430), (1000, 470), (1120, 520), (1250, 580),
          (1400, 640), (1600, 720), (1800, 820), (2000, 920), (2240, 1000), (2500, 1100),
          (2800, 1250), (3150, 1400)),
    "t": ((24, None), (30, 41), (40, 48), (50, 54), (65, 66), (80, 75), (100, 91), (120, 104),
          (140, 122), (160, 134), (180, 146), (200, 166), (225, 180), (250, 196), (280, 218),
          (315, 240), (355, 268), (400, 294), (450, 330), (500, 360), (560, 400), (630, 450),
          (710, 500), (800, 560), (900, 620), (1000, 680), (1120, 780), (1250, 840), (1400, 960),
          (1600, 1050), (1800, 1200), (2000, 1350), (2240, 1500), (2500, 1650), (2800, 1900),
          (3150, 2100)),
    "u": ((3, 18), (6, 23), (10, 28), (18, 33), (24, 41), (30, 48), (40, 60), (50, 70), (65, 87),
          (80, 102), (100, 124), (120, 144), (140, 170), (160, 190), (180, 210), (200, 236),
          (225, 258), (250, 284), (280, 315), (315, 350), (355, 390), (400, 435), (450, 490),
          (500, 540), (560, 600), (630, 660), (710, 740), (800, 840), (900, 940), (1000, 1050),
          (1120, 1150), (1250, 1300), (1400, 1450), (1600, 1600), (1800, 1850), (2000, 2000),
          (2240, 2300), (2500, 2500), (2800, 2900), (3150, 3200)),
    "v": ((14, None), (18, 39), (24, 47), (30, 55), (40, 68), (50, 81), (65, 102), (80, 120),
          (100, 146), (120, 172), (140, 202), (160, 228), (180, 252), (200, 284), (225, 310),
          (250, 340), (280, 385), (315, 425), (355, 475), (400, 530), (450, 595), (500, 660)),
    "x": ((3, 20), (6, 28), (10, 34), (14, 40), (18, 45), (24, 54), (30, 64), (40, 80), (50, 97),
          (65, 122), (80, 146), (100, 178), (120, 210), (140, 248), (160, 280), (180, 310),
          (200, 350), (225, 385), (250, 425), (280, 475), (315, 525), (355, 590), (400, 660),
          (450, 740), (500, 820)),
    "y": ((18, None), (24, 63), (30, 75), (40, 94), (50, 114), (65, 144), (80, 174), (100, 214),
          (120, 254), (140, 300), (160, 340), (180, 380), (200, 425), (225, 470), (250, 520),
          (280, 580), (315, 650), (355, 730), (400, 820), (450, 920), (500, 1000)),
    "z": ((3, 26), (6, 35), (10, 42), (14, 50), (18, 60), (24, 73), (30, 88), (40, 112), (50, 136),
          (65, 172), (80, 210), (100, 258), (120, 310), (140, 365), (160, 415), (180, 465),
          (200, 520), (225, 575), (250, 640), (280, 710), (315, 790), (355, 900), (400, 1000),
          (450, 1100), (500, 1250)),
    "za": ((3, 32), (6, 42), (10, 52), (14, 64), (18, 77), (24, 98), (30, 118), (40, 148),
           (50, 180), (65, 226), (80, 274), (100, 335), (120, 400), (140, 470), (160, 535),
           (180, 600), (200, 670), (225, 740), (250, 820), (280, 920), (315, 1000), (355, 1150),
           (400, 1300), (450, 1450), (500, 1600)),
    "zb": ((3, 40), (6, 50), (10, 67), (14, 90), (18, 108), (24, 136), (30, 160), (40, 200),
           (50, 242), (65, 300), (80, 360), (100, 445), (120, 525), (140, 620), (160, 700),
           (180, 780), (200, 880), (225, 960), (250, 1050), (280, 1200), (315, 1300),
           (355, 1500), (400, 1650), (450, 1850), (500, 2100)),
    "zc": ((3, 60), (6, 80), (10, 97), (14, 130), (18, 150), (24, 188), (30, 218), (40, 274),
           (50, 325), (65, 405), (80, 480), (100, 585), (120, 690), (140, 800), (160, 900),
           (180, 1000), (200, 1150), (225, 1250), (250, 1350), (280, 1550), (315, 1700),
           (355, 1900), (400, 2100), (450, 2400), (500, 2600)),
})  # fmt: skip

# ---------------------------------------------------------------------------------------------
# ISO 286-1:2010 Table 2 — upper fundamental deviations ES of holes J, µm, for the three
# grades the standard tabulates (J6, J7, J8); J is not defined above 500 mm.
# ---------------------------------------------------------------------------------------------
HOLE_J_UPPER_DEVIATIONS_UM: Mapping[str, Column] = MappingProxyType({
    "6": ((3, 2), (6, 5), (10, 5), (18, 6), (30, 8), (50, 10), (80, 13), (120, 16), (180, 18),
          (250, 22), (315, 25), (400, 29), (500, 33)),
    "7": ((3, 4), (6, 6), (10, 8), (18, 10), (30, 12), (50, 14), (80, 18), (120, 22), (180, 26),
          (250, 30), (315, 36), (400, 39), (500, 43)),
    "8": ((3, 6), (6, 10), (10, 12), (18, 15), (30, 20), (50, 24), (80, 28), (120, 34), (180, 41),
          (250, 47), (315, 55), (400, 60), (500, 66)),
})  # fmt: skip

#: ISO 286-1:2010 Table 3 (right-hand columns) — Δ in µm for grades IT3 … IT8, used for
#: K, M, N up to IT8 and P … ZC up to IT7. Δ = ITn − IT(n−1); zero up to 3 mm; not given
#: above 500 mm (no Δ is added there).
DELTA_UM: tuple[tuple[float, tuple[float, ...]], ...] = (
    # up to mm  IT3  IT4  IT5 IT6 IT7 IT8
    (3, (0, 0, 0, 0, 0, 0)),
    (6, (1, 1.5, 1, 3, 4, 6)),
    (10, (1, 1.5, 2, 3, 6, 7)),
    (18, (1, 2, 3, 3, 7, 9)),
    (30, (1.5, 2, 3, 4, 8, 12)),
    (50, (1.5, 3, 4, 5, 9, 14)),
    (80, (2, 3, 5, 6, 11, 16)),
    (120, (2, 4, 5, 7, 13, 19)),
    (180, (3, 4, 6, 7, 15, 23)),
    (250, (3, 4, 6, 9, 17, 26)),
    (315, (4, 4, 7, 9, 20, 29)),
    (400, (4, 5, 7, 11, 21, 32)),
    (500, (5, 5, 7, 13, 23, 34)),
)
_DELTA_GRADES = ("3", "4", "5", "6", "7", "8")

#: ISO 286-1:2010 Table 2, special case: ``(letter, grade, over mm, up to mm) -> ES µm``.
HOLE_SPECIAL_UPPER_DEVIATIONS_UM: Mapping[tuple[str, str, float, float], float] = MappingProxyType(
    {("M", "6", 250.0, 315.0): -9.0}
)

# Letters in the order of the standard.
_SHAFT_ORDER = ("a", "b", "c", "cd", "d", "e", "ef", "f", "fg", "g", "h", "js", "j", "k", "m", "n",
                "p", "r", "s", "t", "u", "v", "x", "y", "z", "za", "zb", "zc")  # fmt: skip
SHAFT_LETTERS: frozenset[str] = frozenset(_SHAFT_ORDER)
HOLE_LETTERS: frozenset[str] = frozenset(letter.upper() for letter in _SHAFT_ORDER)

#: Footnotes to Tables 2 and 4: these letters shall not be used for nominal sizes up to 1 mm.
_NOT_UP_TO_1_MM = frozenset({"a", "b", "A", "B"})
#: Note to Table 1: these grades shall not be used for nominal sizes up to 1 mm.
_GRADES_NOT_UP_TO_1_MM = frozenset({"14", "15", "16", "17", "18"})
#: Letters tabulated only up to 10 mm in the main tables.
_ONLY_UP_TO_10_MM = frozenset({"cd", "ef", "fg", "CD", "EF", "FG"})

_UM_PER_M = 1e6  # micrometres per metre (divide µm by it: exact decimal µm give the nearest m)


# ---------------------------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ToleranceClass:
    """Limit deviations of one ISO 286 tolerance class at one nominal size.

    Attributes:
        designation: canonical designation, letters then grade, e.g. ``"H8"``, ``"js6"``.
        kind: ``"hole"`` (upper-case letters) or ``"shaft"`` (lower-case letters).
        upper: upper limit deviation (ES for a hole, es for a shaft), m.
        lower: lower limit deviation (EI for a hole, ei for a shaft), m.
        nominal_size: nominal size the deviations apply to, m.
    """

    designation: str
    kind: Kind
    upper: float
    lower: float
    nominal_size: float

    def __post_init__(self) -> None:
        owner = f"ToleranceClass {self.designation!r}"
        if self.kind not in ("hole", "shaft"):
            raise StandardsError(f"{owner}: kind must be 'hole' or 'shaft', got {self.kind!r}")
        for name in ("upper", "lower", "nominal_size"):
            if not math.isfinite(getattr(self, name)):
                raise StandardsError(f"{owner}: {name} must be finite")
        if self.upper < self.lower:
            raise StandardsError(f"{owner}: upper deviation {self.upper} m < lower {self.lower} m")
        if self.nominal_size <= 0.0:
            raise StandardsError(f"{owner}: nominal_size must be > 0 m, got {self.nominal_size}")

    @property
    def letter(self) -> str:
        """The fundamental-deviation letters, e.g. ``"JS"``."""
        return self.designation.rstrip("0123456789")

    @property
    def grade(self) -> str:
        """The standard tolerance grade without "IT", e.g. ``"7"`` or ``"01"``."""
        return self.designation[len(self.letter) :]

    @property
    def upper_um(self) -> float:
        """Upper limit deviation, µm."""
        return _to_um(self.upper)

    @property
    def lower_um(self) -> float:
        """Lower limit deviation, µm."""
        return _to_um(self.lower)

    @property
    def tolerance(self) -> float:
        """Width of the tolerance interval (the IT value, rounded for JS/js 7 … 11), m."""
        return (self.upper_um - self.lower_um) / _UM_PER_M

    @property
    def tolerance_um(self) -> float:
        """Width of the tolerance interval, µm."""
        return round(self.upper_um - self.lower_um, 6)

    @property
    def max_size(self) -> float:
        """Upper limit of size, nominal size + upper deviation, m."""
        return self.nominal_size + self.upper

    @property
    def min_size(self) -> float:
        """Lower limit of size, nominal size + lower deviation, m."""
        return self.nominal_size + self.lower


@dataclass(frozen=True)
class Fit:
    """A hole and a shaft of the same nominal size and what their mating gives.

    Clearances are diametral (hole size − shaft size) unless called radial; a negative
    clearance is an interference. All values are derived from the two classes' limits.

    Attributes:
        hole: the hole's tolerance class.
        shaft: the shaft's tolerance class.
    """

    hole: ToleranceClass
    shaft: ToleranceClass

    def __post_init__(self) -> None:
        if self.hole.kind != "hole" or self.shaft.kind != "shaft":
            raise StandardsError(
                f"Fit: needs a hole then a shaft, got {self.hole.kind} {self.hole.designation!r} "
                f"and {self.shaft.kind} {self.shaft.designation!r}"
            )
        if not math.isclose(self.hole.nominal_size, self.shaft.nominal_size, rel_tol=1e-12):
            raise StandardsError(
                f"Fit: hole and shaft must share one nominal size, got {self.hole.nominal_size} m "
                f"and {self.shaft.nominal_size} m"
            )

    @property
    def designation(self) -> str:
        """``"hole/shaft"``, e.g. ``"H8/g7"``."""
        return f"{self.hole.designation}/{self.shaft.designation}"

    @property
    def nominal_size(self) -> float:
        """Common nominal size, m."""
        return self.hole.nominal_size

    @property
    def clearance_min_um(self) -> float:
        """Minimum diametral clearance EI − es, µm (negative: maximum interference)."""
        return round(self.hole.lower_um - self.shaft.upper_um, 6)

    @property
    def clearance_max_um(self) -> float:
        """Maximum diametral clearance ES − ei, µm (negative: minimum interference)."""
        return round(self.hole.upper_um - self.shaft.lower_um, 6)

    @property
    def clearance_mean_um(self) -> float:
        """Mean diametral clearance, µm."""
        return round((self.clearance_min_um + self.clearance_max_um) / 2.0, 6)

    @property
    def clearance_min(self) -> float:
        """Minimum diametral clearance, m."""
        return self.clearance_min_um / _UM_PER_M

    @property
    def clearance_max(self) -> float:
        """Maximum diametral clearance, m."""
        return self.clearance_max_um / _UM_PER_M

    @property
    def clearance_mean(self) -> float:
        """Mean diametral clearance, m."""
        return self.clearance_mean_um / _UM_PER_M

    @property
    def radial_clearance_min(self) -> float:
        """Minimum radial clearance (half the diametral one), m."""
        return self.clearance_min_um / 2.0 / _UM_PER_M

    @property
    def radial_clearance_max(self) -> float:
        """Maximum radial clearance, m."""
        return self.clearance_max_um / 2.0 / _UM_PER_M

    @property
    def radial_clearance_mean(self) -> float:
        """Mean radial clearance, m."""
        return self.clearance_mean_um / 2.0 / _UM_PER_M

    @property
    def fit_type(self) -> FitType:
        """``"clearance"``, ``"transition"`` or ``"interference"`` (ISO 286-1:2010, clause 3).

        A clearance fit always has clearance (minimum clearance ≥ 0), an interference fit always
        interference (maximum clearance ≤ 0); anything between is a transition fit.
        """
        if self.clearance_min_um >= 0.0:
            return "clearance"
        if self.clearance_max_um <= 0.0:
            return "interference"
        return "transition"

    def as_dict_um(self) -> dict[str, object]:
        """The fit as plain data in µm (the structure of the ``fit`` command's JSON)."""
        return {
            "hole": _class_dict(self.hole, with_kind=False),
            "shaft": _class_dict(self.shaft, with_kind=False),
            "fit_type": self.fit_type,
            "clearance_um": {
                "min": self.clearance_min_um,
                "max": self.clearance_max_um,
                "mean": self.clearance_mean_um,
            },
            "radial_clearance_um": {
                "min": round(self.clearance_min_um / 2.0, 6),
                "max": round(self.clearance_max_um / 2.0, 6),
                "mean": round(self.clearance_mean_um / 2.0, 6),
            },
        }


def _class_dict(tc: ToleranceClass, *, with_kind: bool) -> dict[str, object]:
    data: dict[str, object] = {"designation": tc.designation}
    if with_kind:
        data["kind"] = tc.kind
    data["upper_um"] = tc.upper_um
    data["lower_um"] = tc.lower_um
    return data


def class_as_dict_um(tc: ToleranceClass) -> dict[str, object]:
    """One class as plain data in µm (the structure of the ``fit`` command's JSON for a class)."""
    return _class_dict(tc, with_kind=True)


# ---------------------------------------------------------------------------------------------
# Public lookups
# ---------------------------------------------------------------------------------------------
def standard_tolerance(grade: str | int, size: float) -> float:
    """The standard tolerance IT``grade`` at a nominal size (ISO 286-1:2010 Table 1, Table A.1).

    Args:
        grade: ``"IT7"``, ``"7"`` or ``7``; ``"IT01"``/``"01"`` and ``"IT0"``/``"0"``/``0`` for
            the two finest grades.
        size: nominal size, m (0 < size ≤ 3.15 m).

    Returns:
        The standard tolerance, m.

    Raises:
        StandardsError: unknown grade, size outside the standard, or a grade not defined at that
            size (IT01/IT0 above 500 mm, IT14 … IT18 up to 1 mm).
    """
    return _standard_tolerance_um(_parse_grade(grade), _size_mm(size)) / _UM_PER_M


def size_range_mm(size: float) -> tuple[float, float]:
    """The main nominal size range of ISO 286-1 Table 1 that ``size`` (m) falls in, in mm.

    Returns:
        ``(over, up_to_and_including)``; the first range is ``(0.0, 3.0)``.
    """
    lower, upper, _ = _row(STANDARD_TOLERANCES_UM, _size_mm(size))
    return float(lower), float(upper)


def parse_designation(text: str) -> tuple[str, str, Kind]:
    """Split a tolerance-class designation into ``(letters, grade, kind)``.

    Upper-case letters make a hole, lower-case a shaft; whitespace around the parts is ignored.

    Example:
        ``parse_designation(" JS7 ")`` gives ``("JS", "7", "hole")``.

    Raises:
        StandardsError: the text is not a letter code followed by a grade, mixes cases, or
            names a letter or grade ISO 286 does not have.
    """
    if not isinstance(text, str):
        raise StandardsError(f"a tolerance class must be given as text such as 'H7', got {text!r}")
    stripped = text.strip()
    match = re.fullmatch(r"([A-Za-z]+)\s*(\d+)", stripped)
    if match is None:
        raise StandardsError(
            f"cannot read {text!r} as an ISO 286 tolerance class: expected fundamental-deviation "
            "letters (A … ZC for holes, a … zc for shafts) followed by a standard tolerance grade "
            "(01, 0, 1 … 18), e.g. H7, g6, JS7"
        )
    letters, grade = match.groups()
    if letters.isupper():
        kind: Kind = "hole"
        known = HOLE_LETTERS
    elif letters.islower():
        kind = "shaft"
        known = SHAFT_LETTERS
    else:
        raise StandardsError(
            f"{stripped!r}: write the letters all in upper case for a hole ({letters.upper()}{grade}) "
            f"or all in lower case for a shaft ({letters.lower()}{grade})"
        )
    if letters not in known:
        order = [letter.upper() if kind == "hole" else letter for letter in _SHAFT_ORDER]
        raise StandardsError(
            f"{stripped!r}: ISO 286 has no fundamental deviation {letters!r}; {kind}s use "
            f"{' '.join(order)}"
        )
    if grade not in GRADES:
        raise StandardsError(
            f"{stripped!r}: ISO 286 has no standard tolerance grade IT{grade}; the grades are "
            "IT01, IT0, IT1 … IT18"
        )
    return letters, grade, kind


def tolerance_class(designation: str, size: float, *, round_js: bool = True) -> ToleranceClass:
    """Limit deviations of a tolerance class such as ``"H8"``, ``"g7"`` or ``"JS7"``.

    Args:
        designation: fundamental-deviation letters and grade; upper case for a hole, lower
            case for a shaft.
        size: nominal size, m (0 < size ≤ 3.15 m; some letters cover less).
        round_js: for JS/js 7 … 11, round an odd IT value in µm down to the even value below
            before halving, as the footnotes of ISO 286-1 Tables 2 and 4 allow and the tables
            of ISO 286-2 do (e.g. JS7 over 18 up to 30 mm: ±10 µm instead of ±10.5 µm).

    Returns:
        The class with its upper and lower limit deviations.

    Raises:
        StandardsError: unknown designation, a size outside the standard, or a class the
            standard does not define at that size (e.g. T below 24 mm, J9, K9 above 3 mm).
    """
    letters, grade, kind = parse_designation(designation)
    size_mm = _size_mm(size)
    canonical = f"{letters}{grade}"
    if letters in _NOT_UP_TO_1_MM and size_mm <= 1.0:
        raise StandardsError(
            f"{canonical}: fundamental deviations A, B, a and b shall not be used for nominal sizes "
            f"up to 1 mm (ISO 286-1:2010, Tables 2 and 4); got {size_mm:g} mm"
        )
    it = _standard_tolerance_um(grade, size_mm, designation=canonical)
    if kind == "shaft":
        upper_um, lower_um = _shaft_limits_um(letters, grade, size_mm, it, round_js)
    else:
        upper_um, lower_um = _hole_limits_um(letters, grade, size_mm, it, round_js)
    return ToleranceClass(
        designation=canonical,
        kind=kind,
        upper=(upper_um + 0.0) / _UM_PER_M,  # + 0.0 turns −0.0 (from EI = −es = −0) into 0.0
        lower=(lower_um + 0.0) / _UM_PER_M,
        nominal_size=size,
    )


def fit(designation: str, size: float, *, round_js: bool = True) -> Fit:
    """A fit written ``"hole/shaft"``, e.g. ``"H8/g7"`` or ``"H7 / k6"``, at a nominal size.

    Args:
        designation: hole class, a slash, shaft class.
        size: common nominal size, m.
        round_js: passed to :func:`tolerance_class`.

    Raises:
        StandardsError: the text is not ``hole/shaft`` or either class is not defined.
    """
    parts = designation.split("/") if isinstance(designation, str) else []
    if len(parts) != 2:
        raise StandardsError(
            f"cannot read {designation!r} as a fit: write the hole class, a slash and the shaft "
            "class, e.g. H8/g7"
        )
    hole_text, shaft_text = parts
    hole_kind = parse_designation(hole_text)[2]
    shaft_kind = parse_designation(shaft_text)[2]
    if hole_kind != "hole" or shaft_kind != "shaft":
        raise StandardsError(
            f"{designation.strip()!r}: a fit is written hole/shaft with the hole in upper case and "
            f"the shaft in lower case, e.g. H8/g7; got a {hole_kind} then a {shaft_kind}"
        )
    return Fit(
        hole=tolerance_class(hole_text, size, round_js=round_js),
        shaft=tolerance_class(shaft_text, size, round_js=round_js),
    )


# ---------------------------------------------------------------------------------------------
# Generic lookup code
# ---------------------------------------------------------------------------------------------
def _to_um(value_m: float) -> float:
    return round(value_m * _UM_PER_M, 6) + 0.0  # + 0.0 turns −0.0 into 0.0


def _size_mm(size: float) -> float:
    """Validate a nominal size in m and return it in mm, snapped to 1 pm to keep boundaries exact."""
    if isinstance(size, bool) or not isinstance(size, int | float) or not math.isfinite(size):
        raise StandardsError(f"nominal size must be a finite length in metres, got {size!r}")
    size_mm = round(float(size) * 1e3, 9)
    if size_mm <= 0.0:
        raise StandardsError(f"nominal size must be > 0 mm, got {size_mm:g} mm")
    if size_mm > MAX_SIZE_MM:
        raise StandardsError(
            f"nominal size {size_mm:g} mm is outside ISO 286-1:2010, which covers sizes up to "
            f"{MAX_SIZE_MM:g} mm"
        )
    return size_mm


def _row(table: Sequence[tuple[float, _T]], size_mm: float) -> tuple[float, float, _T]:
    """The row ``(over, up_to, value)`` whose range holds ``size_mm`` (over < size ≤ up_to)."""
    lower = 0.0
    for upper, value in table:
        if size_mm <= upper:
            return lower, upper, value
        lower = upper
    raise LookupError(f"{size_mm} mm is beyond the last row (internal: callers check the range)")


def _range_text(lower: float, upper: float) -> str:
    if lower <= 0.0:
        return f"up to and including {upper:g} mm"
    return f"over {lower:g} up to and including {upper:g} mm"


def _defined_range(column: Column) -> tuple[float, float]:
    """Sizes (mm) over which a column has values: ``(over, up_to)``."""
    lower = 0.0
    for upper, value in column:
        if value is not None:
            break
        lower = upper
    return lower, column[-1][0]


def _column_value(column: Column, size_mm: float, canonical: str, what: str) -> float:
    """Look ``size_mm`` up in one column, or say over which sizes the column is defined."""
    lower, upper = _defined_range(column)
    if lower < size_mm <= upper:
        value = _row(column, size_mm)[2]
        if value is not None:
            return float(value)
    note = ""
    if what in _ONLY_UP_TO_10_MM:
        note = (
            f" ({', '.join(sorted(_ONLY_UP_TO_10_MM))} are tabulated only up to 10 mm, mainly "
            "for precision mechanics and watchmaking)"
        )
    raise StandardsError(
        f"{canonical}: ISO 286-1:2010 defines fundamental deviation {what} only for nominal sizes "
        f"{_range_text(lower, upper)}; {size_mm:g} mm is outside{note}"
    )


def _parse_grade(grade: str | int) -> str:
    if isinstance(grade, bool):
        raise StandardsError(f"unknown standard tolerance grade {grade!r}")
    text = str(grade).strip().upper()
    text = text.removeprefix("IT")
    if text not in GRADES:
        raise StandardsError(
            f"unknown standard tolerance grade {grade!r}; ISO 286-1 has IT01, IT0, IT1 … IT18"
        )
    return text


def _standard_tolerance_um(grade: str, size_mm: float, designation: str | None = None) -> float:
    who = f"{designation}: " if designation else ""
    if grade in _GRADES_NOT_UP_TO_1_MM and size_mm <= 1.0:
        raise StandardsError(
            f"{who}standard tolerance grades IT14 to IT18 shall not be used for nominal sizes up to "
            f"1 mm (ISO 286-1:2010, Table 1); got IT{grade} at {size_mm:g} mm"
        )
    if grade in ("01", "0"):
        last = STANDARD_TOLERANCES_IT01_IT0_UM[-1][0]
        if size_mm > last:
            raise StandardsError(
                f"{who}IT{grade} is tabulated only for nominal sizes up to {last:g} mm "
                f"(ISO 286-1:2010, Table A.1); got {size_mm:g} mm"
            )
        return _row(STANDARD_TOLERANCES_IT01_IT0_UM, size_mm)[2][0 if grade == "01" else 1]
    return _row(STANDARD_TOLERANCES_UM, size_mm)[2][int(grade) - 1]


def _grade_rank(grade: str) -> int:
    """Order of a grade: IT01 → −1, IT0 → 0, ITn → n."""
    return -1 if grade == "01" else int(grade)


def _js_half_um(it: float, grade: str, round_js: bool) -> float:
    """Half the tolerance for JS/js, with the even-rounding rule for grades 7 … 11."""
    if round_js and 7 <= _grade_rank(grade) <= 11 and it == int(it) and int(it) % 2 == 1:
        it -= 1.0
    return it / 2.0


def _delta_um(grade: str, size_mm: float, canonical: str) -> float:
    """Δ of Table 3 for sizes over 3 up to 500 mm (zero up to 3 mm; callers skip >500 mm)."""
    if size_mm <= 3.0:
        return 0.0
    if grade not in _DELTA_GRADES:
        raise StandardsError(
            f"{canonical}: over 3 mm this class needs the correction Δ, which ISO 286-1:2010 "
            f"Table 3 gives only for IT3 to IT8; IT{grade} is not defined at {size_mm:g} mm"
        )
    return _row(DELTA_UM, size_mm)[2][_DELTA_GRADES.index(grade)]


def _shaft_limits_um(
    letter: str, grade: str, size_mm: float, it: float, round_js: bool
) -> tuple[float, float]:
    """``(es, ei)`` of a shaft in µm (ISO 286-1:2010 Tables 4 and 5)."""
    canonical = f"{letter}{grade}"
    if letter == "js":
        half = _js_half_um(it, grade, round_js)
        return half, -half
    if letter in SHAFT_UPPER_DEVIATIONS_UM:
        es = _column_value(SHAFT_UPPER_DEVIATIONS_UM[letter], size_mm, canonical, letter)
        return es, es - it
    if letter == "j":
        if grade not in SHAFT_J_LOWER_DEVIATIONS_UM:
            raise StandardsError(
                f"{canonical}: ISO 286-1:2010 Table 4 defines shaft j only for grades j5, j6, j7 "
                "(up to 500 mm) and j8 (up to 3 mm); use js for other grades"
            )
        ei = _column_value(SHAFT_J_LOWER_DEVIATIONS_UM[grade], size_mm, canonical, canonical)
        return ei + it, ei
    if letter == "k":
        ei = 0.0
        if 4 <= _grade_rank(grade) <= 7:
            ei = _column_value(SHAFT_K_IT4_TO_IT7_UM, size_mm, canonical, letter)
        return ei + it, ei
    ei = _column_value(SHAFT_LOWER_DEVIATIONS_UM[letter], size_mm, canonical, letter)
    return ei + it, ei


def _hole_limits_um(
    letter: str, grade: str, size_mm: float, it: float, round_js: bool
) -> tuple[float, float]:
    """``(ES, EI)`` of a hole in µm (ISO 286-1:2010 Tables 2 and 3)."""
    canonical = f"{letter}{grade}"
    shaft_letter = letter.lower()
    rank = _grade_rank(grade)
    if letter == "JS":
        half = _js_half_um(it, grade, round_js)
        return half, -half
    if shaft_letter in SHAFT_UPPER_DEVIATIONS_UM:  # A … H: EI = −es
        ei_hole = -_column_value(
            SHAFT_UPPER_DEVIATIONS_UM[shaft_letter], size_mm, canonical, letter
        )
        return ei_hole + it, ei_hole
    if letter == "J":
        if grade not in HOLE_J_UPPER_DEVIATIONS_UM:
            raise StandardsError(
                f"{canonical}: ISO 286-1:2010 Table 2 defines hole J only for grades J6, J7 and J8 "
                "(up to 500 mm); use JS for other grades"
            )
        es_hole = _column_value(HOLE_J_UPPER_DEVIATIONS_UM[grade], size_mm, canonical, canonical)
        return es_hole, es_hole - it
    with_delta = 3.0 < size_mm <= 500.0
    if letter == "K":
        if rank > 8 and size_mm > 3.0:
            raise StandardsError(
                f"{canonical}: ISO 286-1:2010 Table 2 defines hole K above IT8 only for nominal "
                f"sizes up to 3 mm; got {size_mm:g} mm (use K8 or finer, or JS/H)"
            )
        # Table 2 writes K up to IT8 as "−k + Δ" with k the IT4 … IT7 value of Table 5.
        es_hole = -_column_value(SHAFT_K_IT4_TO_IT7_UM, size_mm, canonical, letter)
        if with_delta:
            es_hole += _delta_um(grade, size_mm, canonical)
    elif letter == "N" and rank > 8 and size_mm <= 500.0:
        if size_mm <= 1.0:
            raise StandardsError(
                f"{canonical}: fundamental deviation N above IT8 shall not be used for nominal "
                f"sizes up to 1 mm (ISO 286-1:2010, Table 3); got {size_mm:g} mm"
            )
        es_hole = -4.0 if size_mm <= 3.0 else 0.0
    else:  # M, N up to IT8; P … ZC
        es_hole = -_column_value(
            SHAFT_LOWER_DEVIATIONS_UM[shaft_letter], size_mm, canonical, letter
        )
        delta_limit = 8 if letter in ("M", "N") else 7
        if with_delta and rank <= delta_limit:
            es_hole += _delta_um(grade, size_mm, canonical)
    lower, upper, _ = _row(STANDARD_TOLERANCES_UM, size_mm)
    special = HOLE_SPECIAL_UPPER_DEVIATIONS_UM.get((letter, grade, lower, upper))
    if special is not None:
        es_hole = special
    return es_hole, es_hole - it
