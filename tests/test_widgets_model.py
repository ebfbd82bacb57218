import json

import numpy as np
import pytest

from branchnb.widgets.model import AnnotationModel, Shape


def test_polyline_vertex_by_vertex_with_undo_redo():
    m = AnnotationModel()
    events = []
    m.observe(events.append)
    i = m.add_shape("polyline", [(1, 1)], radii=[2.0], closed=False)
    m.append_point(i, (5, 5), radius=3.0)
    m.append_point(i, (9, 4))
    assert m.shapes[0].radii.tolist() == [2.0, 3.0, 3.0]
    assert m.open_polyline() == 0
    m.set_closed(i)
    assert m.open_polyline() is None
    assert m.undo() and m.undo()
    assert len(m.shapes[0].points) == 2
    assert m.redo()
    assert len(m.shapes[0].points) == 3
    assert [e.type for e in events] == ["add", "append", "append", "update", "undo", "undo", "redo"]


def test_new_edit_clears_redo_and_undo_limit():
    m = AnnotationModel(max_undo=3)
    for k in range(5):
        m.add_shape("point", [(k, k)])
    assert sum(1 for _ in iter(m.undo, False)) == 3
    m.add_shape("point", [(0, 0)])
    assert not m.can_redo


def test_set_radius_move_remove_clear():
    m = AnnotationModel()
    m.add_shape("polyline", [(0, 0), (4, 0)], radii=[1.0, 1.0])
    m.set_radius(0, 1, 5.0)
    m.move_vertex(0, 0, (1, 2))
    assert m.shapes[0].radii[1] == 5.0 and m.shapes[0].points[0].tolist() == [1.0, 2.0]
    m.add_shape("scribble", [(0, 0), (1, 1)], label="trunk")
    m.remove_shape(0)
    assert [s.kind for s in m.shapes] == ["scribble"]
    m.clear()
    assert len(m) == 0
    m.undo()
    assert len(m) == 1


def test_json_round_trip():
    m = AnnotationModel()
    m.add_shape("polyline", [(0, 0), (4, 3)], radii=[1.0, 2.0], meta={"parent": [0, 1]})
    m.add_shape("scribble", [(0, 0), (1, 1)], label="crown")
    m.add_shape("point", [(7.5, 2.25)])
    back = AnnotationModel.from_json(m.to_json())
    assert [s.to_dict() for s in back.shapes] == [s.to_dict() for s in m.shapes]
    m2 = AnnotationModel()
    m2.load_json(m.to_json())
    assert len(m2) == 3 and m2.undo() and len(m2) == 0


def test_nearest_vertex():
    m = AnnotationModel()
    m.add_shape("polyline", [(0, 0), (10, 0)], radii=[1.0, 1.0])
    m.add_shape("polyline", [(0, 10), (10, 10)], radii=[1.0, 1.0])
    assert m.nearest_vertex((9, 9)) == (1, 1)
    assert m.nearest_vertex((5, 5), max_distance=2) is None
    assert m.nearest_vertex((9, 9), exclude=1) == (0, 1)


@pytest.mark.parametrize("call,exc,match", [
    (lambda m: m.add_shape("circle", [(0, 0)]), ValueError, "kind must be one of"),
    (lambda m: m.add_shape("stroke", []), ValueError, "at least 1"),
    (lambda m: m.add_shape("stroke", [(0, np.nan)]), ValueError, "NaN"),
    (lambda m: m.add_shape("polyline", [(0, 0)], radii=[-1.0]), ValueError, "radii"),
    (lambda m: m.add_shape("scribble", [(0, 0)], label=3), TypeError, "label"),
    (lambda m: m.remove_shape(5), ValueError, "out of range"),
    (lambda m: m.load_json("not json"), ValueError, "not valid annotation JSON"),
    (lambda m: m.load_json(json.dumps({"shapes": [{"kind": "point"}]})), ValueError, "shapes\\[0\\]"),
])
def test_bad_input(call, exc, match):
    m = AnnotationModel()
    with pytest.raises(exc, match=match):
        call(m)
    assert len(m) == 0 and not m.can_undo  # nothing half-done


def test_shape_validation():
    s = Shape("point", [(1, 2)])
    assert s.radii is None and s.closed
