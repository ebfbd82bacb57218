"""Furcation model: where branches split, learnt with a linear SVM.

Every vertex ``i`` of every input branch is described by its *non-causal*
window of ``2k + 1`` (turning angle, thickness) pairs centred on ``i``
plus ``n-`` and ``n+``, the index distances to the previous / next
furcation on the branch (or to its start / end). Vertices where a child
branch starts are labelled +1, the others -1, and a linear SVM
(scikit-learn ``LinearSVC``, features standardised, classes balanced)
separates them.

Probabilities: with at least 3 furcations and 3 other vertices the SVM
is wrapped in ``CalibratedClassifierCV(method="sigmoid")`` (Platt
scaling, cross-validated); with fewer, the decision value ``f`` is mapped
through the logistic ``1 / (1 + exp(-f))``. Either way the ranking of
vertices -- all the synthesis needs -- is the SVM's.

On a synthesized branch the ``d`` vertices of highest probability become
furcations (greedily: after each pick ``n-``/``n+`` change and the
probabilities are recomputed), optionally at least ``min_spacing``
vertices apart. ``d`` is drawn from the input's children-per-branch
distribution (among input branches of similar length) unless the user
sets it. Beyond the paper (issue 23), one-pen line art in a band draws it among the
input branches of the same generation, per length (:meth:`FurcationModel.sample_d`),
and its fill rounds respect :meth:`FurcationModel._child_quota`: a vine's leaf
stubs and a band's strand pieces, which have no children, grow none. A
child's first segment is then chosen by comparing the parent's non-causal
window at the furcation with the parent windows at every input furcation (the bending model's ``Q``); the causal model
continues the child from there.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core.structure import Structure
from .bending import branch_elements, markov_dist

__all__ = ["FurcationModel", "furcation_features", "vertex_angles", "window_features"]


def vertex_angles(points) -> np.ndarray:
    """Turning angle at every vertex (0 at the two ends), ``(N,)``.

    Parameters
    ----------
    points : (N, 2) array_like
        Vertices (x, y) of one branch (pixels).

    Returns
    -------
    (N,) ndarray
        Turning angle at each vertex (radians, positive when turning from +x
        towards +y); 0 at both ends.

    Examples
    --------
    >>> vertex_angles([(0, 0), (1, 0), (1, 1)]).round(4).tolist()
    [0.0, 1.5708, 0.0]
    """
    p = np.asarray(points, np.float64)
    out = np.zeros(len(p))
    if len(p) >= 3:
        out[1:-1] = branch_elements(p, np.ones(len(p)))[0]
    return out


def window_features(av: np.ndarray, rv: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Non-causal windows of ``2k + 1`` angles and thicknesses centred on each vertex.

    Angles are padded with 0 (straight) and thicknesses with the end value.

    Parameters
    ----------
    av : (N,) array_like
        Turning angle of every vertex (radians), as :func:`vertex_angles`.
    rv : (N,) array_like
        Thickness r of every vertex (pixels).
    k : int
        Half window: each window holds ``2k + 1`` vertices.

    Returns
    -------
    wa, wr : (N, 2k + 1) ndarray
        Windows of angles and thicknesses, vertex ``i`` in the middle
        column.
    """
    av = np.asarray(av, np.float64)
    rv = np.asarray(rv, np.float64)
    # np.pad(av, k) and np.pad(rv, k, mode="edge"), without np.pad's per-call overhead (the synthesis
    # loop calls this once per furcation)
    pa = np.concatenate([np.zeros(k), av, np.zeros(k)])
    pr = np.concatenate([np.full(k, rv[0]), rv, np.full(k, rv[-1])]) if len(rv) else np.zeros(2 * k)
    idx = np.arange(len(av))[:, None] + np.arange(2 * k + 1)[None, :]
    return pa[idx], pr[idx]


def _gaps(n: int, furcations) -> tuple[np.ndarray, np.ndarray]:
    """``n-`` (distance to the previous furcation or the start) and ``n+`` per vertex."""
    f = np.unique(np.asarray(list(furcations), np.int64))
    i = np.arange(n)
    if len(f) == 0:
        return i.astype(np.float64), (n - 1 - i).astype(np.float64)
    pos = np.searchsorted(f, i, side="left")  # f[pos - 1] < i
    prev = np.where(pos > 0, f[np.minimum(np.maximum(pos - 1, 0), len(f) - 1)], 0)
    posr = np.searchsorted(f, i, side="right")  # f[posr] > i
    nxt = np.where(posr < len(f), f[np.minimum(posr, len(f) - 1)], n - 1)
    return (i - prev).astype(np.float64), (nxt - i).astype(np.float64)


def furcation_features(av, rv, furcations, k: int) -> np.ndarray:
    """Feature matrix ``(N, 2 (2k + 1) + 2)``: windows, then ``n-`` and ``n+``.

    Parameters
    ----------
    av : (N,) array_like
        Turning angle of every vertex (radians).
    rv : (N,) array_like
        Thickness r of every vertex (pixels).
    furcations : iterable of int
        Vertex indices where children start (for ``n-`` and ``n+``).
    k : int
        Half window of the angle/thickness windows.

    Returns
    -------
    (N, 2 (2k + 1) + 2) ndarray
        Per vertex: the angle window, the thickness window, ``n-`` and
        ``n+`` (index distances to the previous / next other furcation, or
        to the branch's start / end).

    Examples
    --------
    >>> F = furcation_features([0.0] * 5, [2.0] * 5, [2], k=1)
    >>> F.shape, F[:, -2:].tolist()
    ((5, 8), [[0.0, 2.0], [1.0, 1.0], [2.0, 2.0], [1.0, 1.0], [2.0, 0.0]])
    """
    wa, wr = window_features(av, rv, k)
    nm, npl = _gaps(len(av), furcations)
    return np.hstack([wa, wr, nm[:, None], npl[:, None]])


def _unroll(clf, method: str) -> list:
    """``[(w, b, A, B)]`` such that ``p = mean_i 1 / (1 + exp(A_i (w_i . x + b_i) + B_i))``."""

    def linear(pipe):
        scaler, svm = pipe[0], pipe[-1]
        scale = np.where(scaler.scale_ > 0, scaler.scale_, 1.0)
        w = svm.coef_[0] / scale
        b = float(svm.intercept_[0] - (scaler.mean_ / scale) @ svm.coef_[0])
        return w, b

    if method == "calibrated":
        out = []
        for cc in clf.calibrated_classifiers_:
            w, b = linear(cc.estimator)
            cal = cc.calibrators[0]
            out.append((w, b, float(cal.a_), float(cal.b_)))
        return out
    w, b = linear(clf)
    return [(w, b, -1.0, 0.0)]


@dataclass
class FurcationModel:
    """The furcation SVM and the input's furcation examples.

    Parameters
    ----------
    k : int
        Half window.
    classifier : sklearn estimator or None
        None if the input has no furcation (synthesis then never branches).
    probability_method : {"calibrated", "sigmoid", "none"}
        How decision values become probabilities: Platt scaling
        (cross-validated), the plain logistic, or no classifier.
    parent_windows_a, parent_windows_r : (F, 2k + 1) ndarray
        Non-causal windows of the parent at each input furcation.
    child_index : (F,) int ndarray
        The input child branch of each furcation.
    children_per_branch, branch_lengths : ndarray
        For drawing ``d``: children count and length (pixels) of every
        input branch.
    branch_generations : ndarray
        Generation of every input branch (0 = root), for drawing ``d`` among
        one generation (:meth:`sample_d`) and :meth:`_child_quota`.
    n_positive, n_negative : int
        Training vertices that are furcations (+1) and that are not (-1).
    """

    k: int
    classifier: object = None
    probability_method: str = "none"
    parent_windows_a: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    parent_windows_r: np.ndarray = field(default_factory=lambda: np.zeros((0, 1)))
    child_index: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    children_per_branch: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    branch_lengths: np.ndarray = field(default_factory=lambda: np.zeros(0))
    branch_generations: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    n_positive: int = 0
    n_negative: int = 0
    #: The fitted classifier unrolled into numpy: per (calibration) fold the
    #: standardised linear decision ``w . x + b`` and the sigmoid ``(A, B)``.
    _linear: list = field(default_factory=list, repr=False)

    @classmethod
    def fit(cls, structure: Structure, k: int, C: float = 1.0) -> FurcationModel:
        """Train on a structure resampled at the synthesis step ``h``.

        Parameters
        ----------
        structure : Structure
            The example, resampled at the synthesis step h.
        k : int
            Half window: windows of ``2k + 1`` vertices.
        C : float, default 1.0
            Regularisation C of the linear SVM (``SynthesisParams.svm_C``).

        Returns
        -------
        FurcationModel
            With ``classifier = None`` when the example has no furcation or no
            other vertex (then synthesis never branches).
        """
        from sklearn.pipeline import make_pipeline
        from sklearn.preprocessing import StandardScaler
        from sklearn.svm import LinearSVC

        X, y = [], []
        pwa, pwr, cidx = [], [], []
        n = len(structure.branches)
        counts = np.zeros(n, np.int64)
        for b in structure.branches:
            if b.parent is not None:
                counts[b.parent] += 1
        for i, b in enumerate(structure.branches):
            N = len(b.points)
            av = vertex_angles(b.points)
            furc = sorted({structure.branches[j].parent_vertex for j in structure.children(i)})
            if N >= 3:
                F = furcation_features(av, b.thickness, furc, k)
                lab = np.full(N, -1)
                lab[[f for f in furc if 0 < f < N - 1]] = 1
                X.append(F[1:-1])
                y.append(lab[1:-1])
            wa, wr = window_features(av, b.thickness, k)
            for j in structure.children(i):
                c = structure.branches[j]
                if len(c.points) < 2:
                    continue
                pwa.append(wa[c.parent_vertex])
                pwr.append(wr[c.parent_vertex])
                cidx.append(j)
        lengths = np.array([b.length for b in structure.branches])
        gens = np.array([structure.generation(i) for i in range(n)], np.int64)
        model = cls(k=int(k), children_per_branch=counts, branch_lengths=lengths, branch_generations=gens,
                    parent_windows_a=np.array(pwa).reshape(-1, 2 * k + 1),
                    parent_windows_r=np.array(pwr).reshape(-1, 2 * k + 1),
                    child_index=np.asarray(cidx, np.int64))
        if not X:
            return model
        X = np.vstack(X)
        y = np.concatenate(y)
        n_pos, n_neg = int((y > 0).sum()), int((y < 0).sum())
        model.n_positive, model.n_negative = n_pos, n_neg
        if n_pos == 0 or n_neg == 0:
            return model
        # random_state: liblinear's coordinate descent shuffles with numpy's global generator, so two
        # fits of one example differed by ~1e-13 (fit_model was not reproducible)
        svm = make_pipeline(StandardScaler(), LinearSVC(C=C, class_weight="balanced", max_iter=5000, random_state=0))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # ConvergenceWarning on tiny inputs
            if n_pos >= 3 and n_neg >= 3:
                from sklearn.calibration import CalibratedClassifierCV

                clf = CalibratedClassifierCV(svm, method="sigmoid", cv=3)
                clf.fit(X, y)
                model.probability_method = "calibrated"
            else:
                clf = svm.fit(X, y)
                model.probability_method = "sigmoid"
        model.classifier = clf
        model._linear = _unroll(clf, model.probability_method)
        return model

    @property
    def can_branch(self) -> bool:
        return self.classifier is not None and len(self.child_index) > 0

    def probabilities(self, points, radii, furcations=()) -> np.ndarray:
        """Furcation probability of every vertex of a branch, ``(N,)``.

        Parameters
        ----------
        points : (N, 2) array_like
            Vertices (x, y) of the branch, resampled at step h (pixels).
        radii : (N,) array_like
            Thickness r of every vertex (pixels).
        furcations : iterable of int, default ()
            Vertices that already carry a child (they set ``n-`` / ``n+``).

        Returns
        -------
        (N,) ndarray
            Probabilities in [0, 1]; all 0 when the model cannot branch or
            N < 3.
        """
        N = len(points)
        if not self.can_branch or N < 3:
            return np.zeros(N)
        F = furcation_features(vertex_angles(points), radii, furcations, self.k)
        return self._proba(F)

    def _proba(self, F: np.ndarray) -> np.ndarray:
        # Same numbers as classifier.predict_proba (tested), without sklearn's
        # per-call overhead inside the synthesis loop.
        out = np.zeros(len(F))
        for w, b, A, B in self._linear:
            f = F @ w + b
            out += 1.0 / (1.0 + np.exp(np.minimum(np.maximum(A * f + B, -50), 50)))
        return out / len(self._linear)

    def choose(self, points, radii, d: int, *, min_spacing: int = 0, existing=(),
               weights=None) -> list[int]:
        """Greedily pick ``d`` furcation vertices of highest probability.

        Vertices 0 and N-1 are excluded, and so are vertices closer than
        ``min_spacing`` (index distance) to an already chosen or
        ``existing`` furcation. ``weights`` (N,), optional, multiplies the
        probabilities (vertices of weight 0 are never chosen): synthesis
        uses it to furcate where there is room to grow.

        Parameters
        ----------
        points : (N, 2) array_like
            Vertices (x, y) of the branch (pixels).
        radii : (N,) array_like
            Thickness r of every vertex (pixels).
        d : int
            Number of furcations to pick (fewer when no vertex is left).
        min_spacing : int, default 0
            Minimum index distance between furcations (0 and 1: only distinct
            vertices).
        existing : iterable of int, default ()
            Vertices that already carry a child.
        weights : (N,) array_like, optional
            Multiplies the probabilities; vertices of weight 0 are never chosen.
            None = all 1.

        Returns
        -------
        list of int
            The chosen vertex indices, sorted.
        """
        N = len(points)
        chosen: list[int] = []
        furc = list(existing)
        if not self.can_branch or N < 3 or d <= 0:
            return chosen
        # the windows do not change from one pick to the next, only n- and n+ do: the features are
        # furcation_features(vertex_angles(points), radii, furc, k), built the same way
        wa, wr = window_features(vertex_angles(points), radii, self.k)
        wgt = None if weights is None else np.asarray(weights, np.float64)
        for _ in range(int(d)):
            nm, npl = _gaps(N, furc)
            p = self._proba(np.hstack([wa, wr, nm[:, None], npl[:, None]]))
            ok = np.ones(N, bool) if wgt is None else wgt > 0
            if wgt is not None:
                p = p * wgt
            ok[0] = ok[-1] = False
            for f in furc:
                lo, hi = max(f - max(min_spacing, 1) + 1, 0), min(f + max(min_spacing, 1), N)
                ok[lo:hi] = False
            if not ok.any():
                break
            v = int(np.flatnonzero(ok)[np.argmax(p[ok])])
            chosen.append(v)
            furc.append(v)
        return sorted(chosen)

    def _pool(self, generation: int | None) -> np.ndarray:
        """Indices of the input branches of ``generation`` (the deepest one there is if deeper; all when
        None or when the generations are unknown)."""
        g = getattr(self, "branch_generations", None)   # None: a model pickled before branching60
        if generation is None or g is None or len(g) != len(self.children_per_branch) or not len(g):
            return np.arange(len(self.children_per_branch))
        return np.flatnonzero(g == min(int(generation), int(g.max())))

    def sample_d(self, length: float, rng: np.random.Generator, bandwidth: float = 0.5,
                 generation: int | None = None) -> int:
        """Draw ``d`` from the children counts of input branches of similar length.

        Input branches are weighted by ``exp(-log(L / L_b)^2 / (2 bw^2))``.

        Parameters
        ----------
        length : float
            Length of the synthesized branch (pixels).
        rng : numpy.random.Generator
            Random generator.
        bandwidth : float, default 0.5
            Width ``bw`` of the length kernel, in log units (0.5: a branch twice
            as long weighs ``exp(-0.96) ~ 0.38``).
        generation : int, optional
            Draw among the input branches of this generation only (the deepest
            one there is if deeper; beyond the paper, issue 23: a vine's leaf
            stubs and a band's strand pieces have no children, though as long as
            a river's side branches that do), and a branch shorter than the drawn
            one gets its children per length. None = among all, as the paper.

        Returns
        -------
        int
            ``d``, the number of furcations (0 for a model without input
            branches or ``length <= 0``).

        Examples
        --------
        >>> fm = FurcationModel(k=1, children_per_branch=np.array([3, 0]), branch_lengths=np.array([100.0, 90.0]),
        ...                     branch_generations=np.array([0, 1]))
        >>> fm.sample_d(95.0, np.random.default_rng(0), generation=1)
        0
        """
        if len(self.children_per_branch) == 0 or length <= 0:
            return 0
        idx = self._pool(generation)
        L = np.maximum(self.branch_lengths[idx], 1e-6)
        w = np.exp(-np.log(length / L) ** 2 / (2 * bandwidth ** 2))
        if w.sum() <= 0:
            w = np.ones_like(w)
        from .model import _choice  # model imports this module

        j = idx[_choice(rng, w / w.sum())]
        d = int(self.children_per_branch[j])
        if generation is not None and d and length < self.branch_lengths[j]:
            # as many per length as the drawn branch: a band's root that stopped at a sixth of the example's
            # took all of its 9 children (rounded at random, so the mean count per length is the drawn one's)
            x = d * length / max(float(self.branch_lengths[j]), 1e-9)
            d = int(np.floor(x)) + int(rng.random() < x - np.floor(x))
        return d

    def _child_quota(self, length: float, generation: int, slack: float = 1.25) -> int:
        """How many children a synthesized branch of ``length`` and ``generation`` may carry at most: its
        generation's children per length in the input times ``length`` times ``slack``, rounded.

        Beyond the paper (issue 23): the fill rounds, which furcate grown branches again until the domain is
        as covered as the example, count against it; without it a border vine whose leaf stubs have no
        children grew twigs on twigs to fill its band (45 branches where the example has 20).

        Parameters
        ----------
        length : float
            Length of the synthesized branch (pixels).
        generation : int
            Its generation (0 = root; the deepest input generation if deeper).
        slack : float, default 1.25
            Factor on the input's rate.

        Returns
        -------
        int
            The largest number of children (0: the input's branches of that generation have none).

        Examples
        --------
        >>> fm = FurcationModel(k=1, children_per_branch=np.array([4, 0, 0]),
        ...                     branch_lengths=np.array([400.0, 50.0, 60.0]), branch_generations=np.array([0, 1, 1]))
        >>> fm._child_quota(160.0, 0), fm._child_quota(160.0, 1)
        (2, 0)
        """
        idx = self._pool(generation)
        if not len(idx):
            return 0
        rate = float(self.children_per_branch[idx].sum()) / max(float(self.branch_lengths[idx].sum()), 1e-9)
        return int(np.floor(rate * max(float(length), 0.0) * float(slack) + 0.5))

    def child_quality(self, window_a, window_r, subset=None) -> np.ndarray:
        """Q of every input furcation for a synthesized parent window, ``(F,)``.

        Parameters
        ----------
        window_a : (2k + 1,) array_like
            The synthesized parent's non-causal window of turning angles
            (radians) at the new furcation.
        window_r : (2k + 1,) array_like
            Its window of thicknesses (pixels).
        subset : int array_like, optional
            Only these input furcations (positions in ``child_index``); None = all.

        Returns
        -------
        (F,) ndarray
            ``Q = dist(alpha) * dist(r)`` against the parent window of every
            input furcation; empty when the input has none.
        """
        if len(self.child_index) == 0:
            return np.zeros(0)
        wa, wr = self.parent_windows_a, self.parent_windows_r
        if subset is not None:
            wa, wr = wa[subset], wr[subset]
        return markov_dist(wa, window_a) * markov_dist(wr, window_r)
