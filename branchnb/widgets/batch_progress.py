"""A notebook progress bar for :func:`branchnb.batch.run_batch` (the batch code stays widget-free)."""

from __future__ import annotations

from .feedback import ProgressBar

__all__ = ["BatchProgress"]


class BatchProgress:
    """Shows a :class:`ProgressBar` with done/failed counts; ``close`` prints the summary on it.

    The bar is displayed in the notebook output on construction.

    Parameters
    ----------
    total : int
        Number of items the batch makes.
    initial : int
        Items already done (a resumed batch).
    description : str
        Label left of the bar.

    Examples
    --------
    >>> bar = BatchProgress(10, description="trees")       # doctest: +SKIP
    >>> bar.advance(3, failed=1)                           # doctest: +SKIP
    >>> bar.close("10 made, 1 failed")                     # doctest: +SKIP
    """

    def __init__(self, total: int, initial: int = 0, description: str = "batch"):
        from IPython.display import display

        self.total, self.done, self.failed = int(total), int(initial), 0
        self.bar = ProgressBar(description=description)
        display(self.bar)
        self._show()

    def _show(self) -> None:
        extra = f", {self.failed} failed" if self.failed else ""
        self.bar.update(self.done / max(self.total, 1), f"{self.done}/{self.total}{extra}")

    def advance(self, n: int, failed: int = 0) -> None:
        """Count ``n`` more finished items, ``failed`` of which failed, and redraw the bar.

        Parameters
        ----------
        n : int
            Items finished since the last call (failed ones included).
        failed : int
            How many of them failed; the bar then says "k failed".
        """
        self.done += n
        self.failed += failed
        self._show()

    def close(self, summary=None) -> None:
        """End of the batch: show ``summary`` on the bar (the counts stay if None).

        Parameters
        ----------
        summary : object, optional
            The batch's summary (shown with ``str``).
        """
        if summary is not None:
            self.bar.update(self.done / max(self.total, 1), str(summary))
