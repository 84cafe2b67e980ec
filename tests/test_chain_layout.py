"""The chain window's layout (``models.chain._layout``): the one place its parameter and state slot
numbers are made. The builder and the loop both read it; these checks are pure Python (no compile)."""

import pytest

from bifurcation.models.chain._layout import WindowParams, WindowState


@pytest.mark.parametrize("m, n_pieces, drop", [(1, 1, False), (4, 1, True), (4, 3, False), (8, 2, True)])
def test_pack_puts_every_value_at_its_named_slot(m, n_pieces, drop):
    lay = WindowParams(m, n_pieces, drop)
    # distinct values per slot, so a value at a wrong slot cannot go unnoticed
    groups = {name: [100.0 * (g + 1) + i for i in range(m)] for g, name in enumerate(WindowParams.PER_POSITION)}
    pieces = [(i * 7) % n_pieces for i in range(m)] if n_pieces > 1 else None
    values = lay.pack(nu=1.5, nu_f=2.5, l2=3.5, **groups, pieces=pieces, drop=(0.25, 0.75) if drop else ())
    assert len(values) == lay.size
    assert [values[lay.index(n)] for n in WindowParams.GLOBALS] == [1.5, 2.5, 3.5]
    for name, column in groups.items():
        assert [values[lay.at(name, i)] for i in range(m)] == column
    if n_pieces > 1:
        for i in range(m):
            assert [values[lay.selector(k, i)] for k in range(n_pieces)] == [float(k == pieces[i])
                                                                             for k in range(n_pieces)]
    if drop:
        assert (values[lay.index("sigma")], values[lay.index("c")]) == (0.25, 0.75)
        assert lay.index("c") == lay.size - 1   # the σ = 0 layout is this one without its last two slots
    # every slot is named exactly once
    named = [lay.index(n) for n in WindowParams.GLOBALS + (WindowParams.DROP if drop else ())]
    named += [lay.at(n, i) for n in WindowParams.PER_POSITION for i in range(m)]
    named += [lay.selector(k, i) for k in range(n_pieces) for i in range(m)] if n_pieces > 1 else []
    assert sorted(named) == list(range(lay.size))


def test_drop_slots_come_last_so_sigma_zero_keeps_its_layout():
    plain, dropped = WindowParams(4, 3), WindowParams(4, 3, drop=True)
    assert dropped.size == plain.size + 2
    assert all(plain.at("selfc", i) == dropped.at("selfc", i) for i in range(4))
    assert plain.selector(2, 3) == dropped.selector(2, 3)


def test_a_per_position_group_is_not_a_global():
    with pytest.raises(KeyError, match=r"use at\('p', i\)"):
        WindowParams(2).index("p")
    with pytest.raises(ValueError, match="m >= 1"):
        WindowParams(0)


def test_state_slots_are_slips_then_velocities_then_the_energy_integrals():
    for m, energy in ((1, False), (4, True), (8, False)):
        lay = WindowState(m, energy)
        order = list(range(lay.size))
        slots = order[lay.slips(m)] + order[lay.velocities(m)] + ([lay.diss, lay.disp] if energy else [])
        assert slots == order                        # every slot named once, in the builder's order
        assert order[lay.velocities(1)] == [lay.v0]
