"""Unclear messages: trace arrays of different lengths or empty
(f2py's "0-th dimension must be fixed to 1441", "unexpected array size"), a ``Decimal``
reported as "the string", and a whole float given to an integer input ("malformed integer
11.0"). Each gave that message (a ValueError, or an InputError naming the wrong thing)
before the fix."""

from __future__ import annotations

import decimal
import fractions

import numpy as np
import pytest

import ringlube
from ringlube import Case, InputError

pytestmark = [
    pytest.mark.unit,
    pytest.mark.filterwarnings("ignore::ringlube.case.origins.SourceEngineDefaultWarning"),
]
FAST = {"nodes": 31, "dpsi_deg": 4.0}
PSI = np.linspace(0.0, 720.0, 1441)
P = np.full(1441, 1.5e5)


@pytest.fixture()
def base() -> Case:
    return Case(name="unclear").with_numerics(**FAST)


@pytest.mark.parametrize(
    "trace, match",
    [
        ((PSI, P[:-1]), "crank angle has 1441 values but pressure 1440"),
        ((PSI[:5], P), "crank angle has 5 values but pressure 1441"),
        ((np.array([]), np.array([])), "trace: 0 points"),
        ((PSI[:1], P[:1]), "trace: 1 points"),
        ((PSI, np.c_[P, P]), r"trace: pressure must be one-dimensional, got shape \(1441, 2\)"),
        ((PSI, ["a"] * 1441), "trace: pressure must be numbers"),
        ((PSI,), "trace: expected a pair"),
    ],
    ids=["short-pressure", "short-angle", "empty", "one-point", "2-D", "text", "one-array"],
)
def test_trace_arrays_refused_naming_argument_and_lengths(base, trace, match):
    with pytest.raises(InputError, match=match) as info:
        ringlube.run(base, trace=trace)
    assert "\n" not in str(info.value)


def test_good_trace_still_runs(base):
    assert ringlube.run(base, trace=(PSI.tolist(), P.tolist())).converged


@pytest.mark.parametrize("number", [decimal.Decimal("1.1e-3"), fractions.Fraction(11, 10000)])
def test_decimal_and_fraction_are_numbers(base, number):
    """A Decimal was written to the deck as "the string"; it is the number it holds."""
    case = base.with_ring(width=number)
    assert case["ring", "width"] == pytest.approx(1.1e-3, rel=1e-15)
    assert ringlube.run(case).energy_loss == ringlube.run(base.with_ring(width=1.1e-3)).energy_loss


@pytest.mark.parametrize("whole", [41.0, np.float64(41.0), decimal.Decimal("41")])
def test_whole_float_for_integer_input_is_the_integer(base, whole):
    """numerics:nodes = 41.0 gave 'malformed integer "41.0"'."""
    case = base.with_numerics(nodes=whole)
    assert case["numerics", "nodes"] == 41 and isinstance(case["numerics", "nodes"], int)
    assert ringlube.run(case).energy_loss == ringlube.run(base.with_numerics(nodes=41)).energy_loss


def test_fractional_float_for_integer_input_is_refused_by_name(base):
    with pytest.raises(InputError, match=r"&numerics nodes: 41\.5 is not a whole number"):
        base.with_numerics(nodes=41.5)


def test_integer_study_variable_refused_by_name(tmp_path):
    """A study samples reals; an integer input as a variable is refused naming it."""
    from ringlube.study.deck import read_study

    (tmp_path / "s.nml").write_text(
        "&study name = 'x', cases = 'a.nml', variables = 'width', 'numerics:nodes',\n"
        "  lower = 0.5e-3, 11, upper = 1.3e-3, 41, objectives = 'energy_loss', 'mixed_share' /\n"
    )
    with pytest.raises(InputError, match=r"'numerics:nodes' is a whole number \(&numerics nodes\)"):
        read_study(tmp_path / "s.nml")


def test_run_designs_integer_variable_whole_or_named(base):
    v, ok, err = ringlube.run_designs(base, ["numerics:nodes"], np.array([[41.0], [41.4]]), ["energy_loss"])
    assert err[0] is None and ok[0]
    assert "&numerics nodes" in err[1] and "integer" in err[1]
