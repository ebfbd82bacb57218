"""What the kit needs from the browser: the device pixel ratio, and one small stylesheet.

Both ride on plain ipywidgets (no front-end extension of our own): an
``<img>`` whose ``onerror`` runs a few lines of JavaScript when the widget
is shown. That works in JupyterLab, the classic notebook and Voilà alike.
"""

from __future__ import annotations

import ipywidgets as widgets
import numpy as np
import traitlets

__all__ = ["PixelRatioProbe", "KitStyle", "backing_ratio"]


def backing_ratio(browser_ratio: float) -> float:
    """The canvas backing-store ratio for a browser's ``devicePixelRatio``.

    Rounded to quarter steps so that a zoomed browser (1.1, 1.25, ...) does not
    make every canvas redraw on each tiny zoom change, and kept in [1, 3].

    Examples
    --------
    >>> backing_ratio(2.0), backing_ratio(1.1), backing_ratio(0.5), backing_ratio(4.0)
    (2.0, 1.0, 1.0, 3.0)
    """
    return float(np.clip(round(float(browser_ratio) * 4) / 4, 1.0, 3.0))


class PixelRatioProbe(widgets.VBox):
    """Reports ``window.devicePixelRatio`` of the browser showing it (via a hidden text box).

    ``ratio`` is 0 until a browser has shown the probe. Canvases size their
    backing store from it (CSS size x ratio), so that they are sharp on
    HiDPI screens and not wastefully large on ordinary ones.

    ``width`` is the CSS width available to the nearest enclosing widget
    with the class ``bnb-fit`` (the width of that widget's parent; 0 when
    there is none or it is not shown), reported again whenever it changes:
    a plot can then be drawn at the size it is shown at instead of being
    squeezed by the browser (which would blur it).
    """

    ratio = traitlets.Float(0.0)
    width = traitlets.Float(0.0)

    def __init__(self):
        self._box = widgets.Text(value="", continuous_update=True,
                                 layout=widgets.Layout(display="none"))
        tag = f"bnb-dpr-{id(self):x}"
        self._box.add_class(tag)
        js = ("var n=0,seen=0;function f(){var e=document.querySelectorAll('.TAG input');"
              "if(!e.length){if(n++<40)setTimeout(f,250);return;}"
              "e.forEach(function(i){var fit=i.closest('.bnb-fit'),p=fit&&fit.parentElement;"
              "if(p&&!seen&&window.ResizeObserver){seen=1;new ResizeObserver(function(){f();}).observe(p);}"
              "var r=String(window.devicePixelRatio||1)+' '+(p?p.clientWidth:0);if(i.value!==r){i.value=r;"
              "i.dispatchEvent(new Event('input',{bubbles:true}));"
              "i.dispatchEvent(new Event('change',{bubbles:true}));}});}f();"
              # a window moved to another screen or a zoomed page changes the ratio: report again
              "if(!window.__bnbDpr){window.__bnbDpr=[];var all=function(){window.__bnbDpr.forEach("
              "function(g){g();});};(function w(){matchMedia('(resolution: '+(window.devicePixelRatio||1)"
              "+'dppx)').addEventListener('change',function(){all();w();},{once:true});})();"
              "window.addEventListener('resize',all);}"
              "window.__bnbDpr.push(function(){n=0;f();});").replace("TAG", tag)
        probe = widgets.HTML(f'<img src="data:," alt="" style="display:none" onerror="{js}">',
                             layout=widgets.Layout(height="0px", overflow="hidden", margin="0"))
        super().__init__([self._box, probe], layout=widgets.Layout(height="0px", margin="0",
                                                                   overflow="hidden"))
        self.add_class("bnb-probe")
        self._box.observe(self._got, names="value")

    def _got(self, change):
        parts = str(change["new"]).split()
        try:
            r = float(parts[0])
            w = float(parts[1]) if len(parts) > 1 else 0.0
        except (ValueError, IndexError):
            return
        if np.isfinite(w) and w >= 0:
            self.width = w
        if np.isfinite(r) and r > 0:
            self.ratio = r


# Click an image of a result view to see it at twice its size (pixels kept sharp), click again to
# shrink it back. One delegated listener per page, installed by the first app shown.
_ZOOM_JS = ("if(!window.__bnbZoom){window.__bnbZoom=1;document.addEventListener('click',function(e){"
            "var t=e.target;if(!t||!t.closest)return;var im=t.closest('.bnb-view img');if(!im)return;"
            "if(im.classList.contains('bnb-big')){im.classList.remove('bnb-big');im.style.removeProperty('width');"
            "im.style.removeProperty('max-width');return;}"
            "var w=im.naturalWidth>im.clientWidth+1?im.naturalWidth:2*im.clientWidth;"
            "im.classList.add('bnb-big');im.style.setProperty('width',w+'px','important');"
            "im.style.setProperty('max-width','none','important');},true);}")

#: A narrow canvas' toolbar on one row: tool names hidden (icons and tooltips stay), 1 px margins.
COMPACT_CSS = """
.bnb-compact .widget-toggle-button{font-size:0;padding:0;margin:1px 1px 1px 0;min-width:0}
.bnb-compact .widget-toggle-button i{font-size:12px;margin:0}
.bnb-compact .widget-toggle-buttons{margin:0 1px 0 0}
.bnb-compact > .widget-button{margin:1px;min-width:0}
.bnb-compact > .widget-button i{font-size:12px;margin:0}
"""

_CSS = COMPACT_CSS + """
.bnb-view img{cursor:zoom-in}
.bnb-view img.bnb-big{cursor:zoom-out;image-rendering:pixelated;position:relative;z-index:5}
.bnb-view .widget-vbox{overflow:visible}
.bnb-stale img{opacity:0.45;filter:grayscale(0.6)}
.bnb-app .bnb-help summary{cursor:pointer;color:#1565c0;font-size:12px}
.bnb-app .bnb-help{font-size:12px;color:#444;line-height:16px;margin:0 0 4px 2px}
.bnb-app .bnb-help ul{margin:2px 0 2px 14px;padding:0}
.bnb-app .bnb-param-label{white-space:nowrap;overflow:hidden;text-overflow:ellipsis;font-size:12px;
  line-height:28px}
.bnb-app .bnb-links a{margin-right:10px}
"""


class KitStyle(widgets.HTML):
    """The kit's stylesheet and the click-to-enlarge handler (an invisible widget, one per app)."""

    def __init__(self):
        super().__init__(f"<style>{_CSS}</style>"
                         f'<img src="data:," alt="" style="display:none" onerror="{_ZOOM_JS}">',
                         layout=widgets.Layout(height="0px", margin="0", overflow="hidden"))
        self.add_class("bnb-probe")
