"""Appendix B's bit maps: the shape operations on 16x16 maps (equations B-1 to B-8) and the
radial map's storage, rotation and comparison.

Pure functions on maps; the pixel work that makes maps (the Star region's block map, label 500's
edge map, the radial map) is NSTAR's (``nstar.bitmaps``, ``nstar.extensions``).

**Rectangular maps** are NSTAR's layout: 16 column words, column 1 (index 0) leftmost, bit 0 the
top row.  Words are taken as 16-bit patterns (a negative 16-bit word from a file is the same
pattern) and returned as ints 0..65535.  Appendix B shifts maps "extended left and right with
0's": every map here lies on an unbounded field of zeros, so

* LSHIFT moves columns left (column j gets column j+1; column 16 is 0), RSHIFT right;
* USHIFT moves rows up (row i gets row i+1: ``word >> 1``), DSHIFT down (``word << 1``);
* V (B-2) and H (B-5) are kept as 16-word maps, so a step at the map's left (top) border, between
  the zero column -1 (row -1) and column 0 (row 0), has no bit in V (H); L (B-3) and T (B-6) use
  the extended V and H, so a region touching the left (top) border has its left (top) edge there,
  as it has its right (bottom) edge at the right (bottom) border.

With the extension, B-3 reduces to ``L = A AND NOT RSHIFT(A)`` (in the region, its left
neighbour not), B-4 to ``R = A AND NOT LSHIFT(A)``, B-6 ``T = A AND NOT DSHIFT(A)``, B-7
``B = A AND NOT USHIFT(A)``; tests/test_model_bitmaps.py checks both forms.

**Radial maps** (Appendix B, "Map Generation"): one word per pie-shaped sector of 22.5 degrees,
bit 0 the innermost of 16 rings, bit 15 the outermost; sectors clockwise as the picture shows
them (angle from the +x axis toward +y, rows running down).  Stored "word with most ones first,
continuing clockwise" (:func:`radial_canonical`; the first such word clockwise from sector 0 on
ties), so a rotation is a change of index (:func:`rotate`) and two radial maps are compared in
all 16 orientations (:func:`radial_compare`).  The same edge operations apply with the
horizontal shifts replaced by rotations that wrap round (``cyclic=True``).
"""

from __future__ import annotations

NWORDS = 16
MASK = 0xFFFF


def _words(a) -> list[int]:
    w = [int(v) & MASK for v in a]
    if len(w) != NWORDS:
        raise ValueError(f"a bit map has {NWORDS} words, got {len(w)}")
    return w


def popcount(word: int) -> int:
    return bin(int(word) & MASK).count("1")


def ones(a) -> int:
    """Number of bits set in a map."""
    return sum(popcount(w) for w in _words(a))


# --- B-1: shape difference -------------------------------------------------------------

def xor(a1, a2) -> tuple[int, ...]:
    """B-1: D = A1 XOR A2, word by word (16 XORs for a whole map)."""
    return tuple(x ^ y for x, y in zip(_words(a1), _words(a2)))


def difference(a1, a2) -> int:
    """The number of bits set in B-1's D: Goshtasby's "closeness of fit" (0 = the same)."""
    return ones(xor(a1, a2))


# --- shifts ------------------------------------------------------------------------------

def lshift(a, cyclic: bool = False) -> tuple[int, ...]:
    """Columns one to the left: column j <- column j+1 (0, or column 0 if ``cyclic``)."""
    w = _words(a)
    return tuple(w[1:] + [w[0] if cyclic else 0])


def rshift(a, cyclic: bool = False) -> tuple[int, ...]:
    """Columns one to the right: column j <- column j-1 (0, or column 15 if ``cyclic``)."""
    w = _words(a)
    return tuple([w[-1] if cyclic else 0] + w[:-1])


def ushift(a) -> tuple[int, ...]:
    """Rows one up: row i <- row i+1 (row 15 <- 0)."""
    return tuple(w >> 1 for w in _words(a))


def dshift(a) -> tuple[int, ...]:
    """Rows one down: row i <- row i-1 (row 0 <- 0)."""
    return tuple((w << 1) & MASK for w in _words(a))


def _and(a, b):
    return tuple(x & y for x, y in zip(a, b))


def _or(*maps):
    out = [0] * NWORDS
    for m in maps:
        out = [x | y for x, y in zip(out, m)]
    return tuple(out)


# --- B-2 .. B-8 ----------------------------------------------------------------------------

def vertical_edges(a, cyclic: bool = False) -> tuple[int, ...]:
    """B-2: V = A XOR LSHIFT(A): a bit in column j where columns j and j+1 differ."""
    return xor(a, lshift(a, cyclic))


def left_edges(a, cyclic: bool = False) -> tuple[int, ...]:
    """B-3: L = A AND RSHIFT(V), V on the zero-extended map (its column -1 is A's column 0)."""
    w = _words(a)
    v = vertical_edges(w, cyclic)
    v_minus1 = v[-1] if cyclic else w[0]          # V(-1) = A(-1) XOR A(0) = A(0)
    return _and(w, (v_minus1,) + v[:-1])


def right_edges(a, cyclic: bool = False) -> tuple[int, ...]:
    """B-4: R = A AND V."""
    return _and(_words(a), vertical_edges(a, cyclic))


def horizontal_edges(a) -> tuple[int, ...]:
    """B-5: H = A XOR USHIFT(A): a bit in row i where rows i and i+1 differ."""
    return xor(a, ushift(a))


def top_edges(a) -> tuple[int, ...]:
    """B-6: T = A AND DSHIFT(H), H on the zero-extended map (its row -1 is A's row 0)."""
    w = _words(a)
    h = horizontal_edges(w)
    return tuple(x & (((hh << 1) | (x & 1)) & MASK) for x, hh in zip(w, h))


def bottom_edges(a) -> tuple[int, ...]:
    """B-7: B = A AND H."""
    return _and(_words(a), horizontal_edges(a))


def vertex_points(a, cyclic: bool = False) -> tuple[int, ...]:
    """B-8: P = (L AND T) OR (L AND B) OR (R AND T) OR (R AND B): the points where a vertical
    and a horizontal edge meet (or an edge has both components)."""
    L, R = left_edges(a, cyclic), right_edges(a, cyclic)
    T, B = top_edges(a), bottom_edges(a)
    return _or(_and(L, T), _and(L, B), _and(R, T), _and(R, B))


OPERATIONS = ("A", "V", "L", "R", "H", "T", "B", "P")


def all_operations(a, cyclic: bool = False) -> dict[str, tuple[int, ...]]:
    """The map and B-2..B-8 of it, by the names of Appendix B."""
    w = tuple(_words(a))
    return {"A": w, "V": vertical_edges(w, cyclic), "L": left_edges(w, cyclic),
            "R": right_edges(w, cyclic), "H": horizontal_edges(w), "T": top_edges(w),
            "B": bottom_edges(w), "P": vertex_points(w, cyclic)}


# --- radial maps ---------------------------------------------------------------------------

def rotate(a, k: int) -> tuple[int, ...]:
    """The map turned by ``k`` sectors: word j <- word (j + k) mod 16 (a change of index)."""
    w = _words(a)
    k %= NWORDS
    return tuple(w[k:] + w[:k])


def radial_canonical(sectors) -> tuple[tuple[int, ...], int]:
    """Appendix B's storage of a radial map given clockwise from sector 0: (the map starting at
    the word with most ones, continuing clockwise; that word's sector index = the orientation,
    in steps of 22.5 degrees).  On ties the first such word clockwise from sector 0."""
    w = _words(sectors)
    counts = [popcount(x) for x in w]
    k = counts.index(max(counts))
    return rotate(w, k), k


def radial_compare(a1, a2) -> tuple[int, int]:
    """Compare two radial maps in all 16 orientations, "much like a logical convolution":
    (fewest differing bits, the rotation k of ``a2`` that gives it; the smallest k on ties)."""
    best = None
    for k in range(NWORDS):
        d = difference(a1, rotate(a2, k))
        if best is None or d < best[0]:
            best = (d, k)
    return best


def shifted_compare(a1, a2, max_shift: int = 3) -> tuple[int, int]:
    """Compare rectangular (edge) maps at horizontal offsets -max_shift..max_shift ("a best
    fit shape match", Appendix B, Edge maps): (fewest differing bits, the offset s, a2's column
    j compared with a1's column j + s; the smallest |s|, then the negative, on ties)."""
    w1, w2 = _words(a1), _words(a2)
    best = None
    for s in sorted(range(-max_shift, max_shift + 1), key=lambda s: (abs(s), s)):
        moved = [0] * NWORDS
        for j in range(NWORDS):
            if 0 <= j + s < NWORDS:
                moved[j + s] = w2[j]
        d = difference(w1, moved)
        if best is None or d < best[0]:
            best = (d, s)
    return best


def from_rows(rows) -> tuple[int, ...]:
    """A map from 16 strings of 16 characters ('#' or '1' set, anything else clear), top row
    first: the readable way to write a map in a test or a note."""
    rows = list(rows)
    if len(rows) != NWORDS or any(len(r) != NWORDS for r in rows):
        raise ValueError("a map is 16 rows of 16 characters")
    return tuple(sum(1 << i for i, r in enumerate(rows) if r[j] in "#1") for j in range(NWORDS))


def to_rows(a, on: str = "#", off: str = ".") -> list[str]:
    """The map as 16 strings, top row first (inverse of :func:`from_rows`)."""
    w = _words(a)
    return ["".join(on if (w[j] >> i) & 1 else off for j in range(NWORDS)) for i in range(NWORDS)]
