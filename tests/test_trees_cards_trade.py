"""cards_hold's trades (issue 24): figures in, decision out, without building clouds."""

import pytest

from branchnb.trees import billboard_cards as bc


def _figures(recall, closed, rim, rrim=1.0, psnr=45.0):
    out = {"psnr": psnr, "rim": rim, "rrim": rrim}
    for y in bc.CHECK_YAWS:
        out[f"recall{y:g}"] = recall
        out[f"closed{y:g}"] = closed
    return out


@pytest.fixture
def figures(monkeypatch):
    table = {}
    monkeypatch.setattr(bc, "_side_figures", lambda cloud: table[cloud])
    return table


def test_cards_keeping_the_inner_outlines_may_open_a_little_more_sky(figures):
    # fruit_pile_0 at 512 px: cards 0.948 recall, 1.6 % sky; superpixels smear (0.60 recall), no sky
    figures["cards"] = _figures(0.948, 0.984, 0.942)
    figures["plain"] = _figures(0.602, 1.0, 0.947, 0.98)
    assert bc.cards_hold("cards", "plain")


def test_sky_beyond_the_trade_or_without_a_recall_gain_falls_back(figures):
    figures["plain"] = _figures(0.602, 1.0, 0.947, 0.98)
    figures["gaps"] = _figures(0.948, 1.0 - bc.SKY_TRADE - 0.005, 0.942)   # cards moved apart
    assert not bc.cards_hold("gaps", "plain")
    figures["alike"] = _figures(0.90, 0.984, 0.99)                        # no recall gain
    figures["plain2"] = _figures(0.89, 1.0, 0.99)
    assert not bc.cards_hold("alike", "plain2")
    assert bc.SKY_TOLERANCE < bc.SKY_TRADE <= 0.02
