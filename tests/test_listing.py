"""The one ACCEPT of the three dialogues (diskfmt.listing.accept)."""

import io

import pytest

from diskfmt.listing import Console, accept, accept_integer


def _console(answers: str):
    out = io.StringIO()
    return Console(out=out, inp=io.StringIO(answers)), out


def test_accept_asks_again_naming_the_bad_answer():
    con, out = _console("abc\n\n2.5\n40000\n-7\n")
    assert con.accept(" N = ") == -7
    text = out.getvalue()
    assert text.count(" N = ") == 5
    assert "** 'abc' is not a number (a whole number is wanted); answer again." in text
    assert "** an empty line is not a number" in text
    assert "** '2.5' is not a number" in text
    assert "** 40000 does not fit a 16-bit INTEGER (-32768..32767); answer again." in text


def test_accept_end_of_input_is_eoferror():
    con, _ = _console("x\n")
    with pytest.raises(EOFError):
        con.accept("? ")


def test_accept_with_a_converter_and_any_terminal():
    said = []
    answers = iter(["feet", "0.75"])

    def convert(t):
        if not t[0].isdigit():
            raise ValueError(f"camera separation '{t}' is not a number")
        return float(t)

    assert accept(lambda p: next(answers), said.append, "DS = ", convert) == 0.75
    assert said == ["** camera separation 'feet' is not a number; answer again."]
    assert accept_integer(" 12 ") == 12
