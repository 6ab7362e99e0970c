"""Property tests: every decoder in diskfmt/layouts.py, given arbitrary bytes,
either returns a result or raises FormatError -- never any other exception.

Inputs mix arbitrary short byte strings (mostly wrong sizes) with files of the
exact expected size whose content is arbitrary: either wholly random (from a
seed) or a constant fill with a few arbitrary bytes patched in, so impossible
content (out-of-range words, bad counts, odd REAL bit patterns) is reached.
"""

import random

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from diskfmt import layouts as L
from diskfmt.layouts import FormatError


DECODERS = [
    (L.decode_vd, (32768,)),
    (L.decode_bi, (30720,)),
    (L.decode_ncont, (12,)),
    (L.decode_slice, (1024, 512)),
    (L.decode_wbmap, (34,)),
    (L.decode_block, (54,)),
    (L.decode_posit, (2560,)),
]


def _sized(size):
    random_file = st.integers(0, 2**32 - 1).map(
        lambda seed: random.Random(seed).randbytes(size))

    def patch(args):
        fill, patches = args
        buf = bytearray([fill]) * size
        for off, val in patches:
            buf[off % size] = val
        return bytes(buf)

    patched = st.tuples(
        st.sampled_from([0x00, 0xFF, 0x80, 0x7F, 0x01, 0x0F, 0x10]),
        st.lists(st.tuples(st.integers(0, size - 1), st.integers(0, 255)), max_size=12),
    ).map(patch)
    return st.one_of(random_file, patched)


def _inputs(sizes):
    near = [s + d for s in sizes for d in (-2, -1, 1, 2)]
    wrong_size = st.one_of(
        st.binary(max_size=80),
        st.sampled_from(near).map(lambda n: bytes(max(n, 0))),
    )
    return st.one_of(wrong_size, *[_sized(s) for s in sizes])


def _check(decoder, data):
    try:
        decoder(data)
    except FormatError as exc:
        assert str(exc).startswith(exc.name + ":")
        assert exc.problem


_SETTINGS = settings(max_examples=60, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])


@pytest.mark.parametrize("decoder, sizes", DECODERS, ids=[d.__name__ for d, _ in DECODERS])
def test_decoder_gives_result_or_format_error(decoder, sizes):
    @_SETTINGS
    @given(_inputs(sizes))
    def prop(data):
        _check(decoder, data)

    prop()


def test_all_decoders_are_covered():
    # If a decoder is added to layouts.py this list must grow with it.
    names = {n for n in dir(L) if n.startswith("decode_")}
    assert names == {d.__name__ for d, _ in DECODERS}


@_SETTINGS
@given(st.binary(max_size=64), st.sampled_from([d for d, _ in DECODERS]))
def test_any_short_bytes_any_decoder(data, decoder):
    _check(decoder, data)
