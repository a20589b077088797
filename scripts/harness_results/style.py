r"""The figure style of every script (one style): pyplot set up for the report, the printed sizes,
colours, writing a figure (save), log ticks, heat maps and label placement.

Every figure is drawn at the width the report prints it at, so that nothing is scaled and the
text is printed at the size set here (8 pt; 7 pt for the numbers in heat-map cells and for
dense keys). paper/main.tex (article, 11pt, a4paper, geometry margin=2.2cm) has
\textwidth = 472.316 pt (measured with \the\textwidth); a figure is included with
width=\linewidth, either in the text (TEXT) or in a minipage{0.49\textwidth} (HALF).
Change these when the report's page layout changes.
"""

import math
import os

TEXT = 472.31595 / 72.27  # in: 6.535
HALF = 0.49 * TEXT        # in: 3.202
FONT = 8.0                # pt: every text of a figure
SMALL = 7.0               # pt: numbers in heat-map cells, keys of many entries (the least)
PALETTE = ["#0072B2", "#E69F00", "#009E73", "#CC79A7", "#D55E00", "#56B4E9", "#F0E442", "#000000"]  # Okabe-Ito
ELIM_STYLE = {"line": {"color": "#D55E00"}, "plane": {"color": "#0072B2"}}  # Okabe-Ito vermilion, blue
# The studies' figures: a colour per detector, a marker per eliminator.
DETECTOR_COLOUR = {"voxel": "#0072B2", "fcl": "#E69F00", "cgal": "#009E73", "hash": "#CC79A7", "bullet": "#D55E00"}
ELIMINATOR_MARKER = {"line": "o", "plane": "s", "projection": "^"}


def pyplot():
    """matplotlib.pyplot with the report's style (one style for every script): text of FONT pt
    (never below SMALL) at the printed size, colour-blind-safe colours, TrueType (type 42) fonts
    in the PDF. Make figures with figsize=(TEXT or HALF, height) and layout="constrained" and
    write them with save(): the files keep exactly that size."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams.update({
        "font.size": FONT, "axes.titlesize": FONT, "axes.labelsize": FONT, "xtick.labelsize": FONT,
        "ytick.labelsize": FONT, "legend.fontsize": FONT, "legend.title_fontsize": FONT, "figure.titlesize": FONT,
        "lines.linewidth": 1.0, "lines.markersize": 4, "axes.linewidth": 0.6, "grid.linewidth": 0.4,
        "xtick.major.width": 0.6, "ytick.major.width": 0.6, "xtick.minor.width": 0.4, "ytick.minor.width": 0.4,
        "xtick.major.size": 3, "ytick.major.size": 3, "xtick.minor.size": 1.8, "ytick.minor.size": 1.8,
        "axes.titlepad": 4, "legend.handlelength": 1.6, "legend.borderaxespad": 0.3,
        "pdf.fonttype": 42, "ps.fonttype": 42, "image.cmap": "viridis",
        "savefig.bbox": None, "figure.dpi": 100, "svg.hashsalt": "harness",
        "figure.constrained_layout.h_pad": 0.02, "figure.constrained_layout.w_pad": 0.02,
        "axes.prop_cycle": matplotlib.cycler(color=PALETTE),
    })
    return plt


def save(fig, base, width=None):
    """base.png (300 dpi) and base.pdf (vector, the one the report includes), both exactly the
    figure's size (no tight bounding box: the size is the printed size). No dates or software
    versions are written, so the files depend only on the data. `width` (in), when given, is
    checked against the figure's width."""
    import matplotlib.pyplot as plt
    w, h = fig.get_size_inches()
    if width is not None and abs(w - width) > 1e-6:
        raise ValueError("%s: figure is %.3f in wide, printed at %.3f in" % (base, w, width))
    os.makedirs(os.path.dirname(base) or ".", exist_ok=True)
    fig.savefig(base + ".png", dpi=300, metadata={"Software": None})
    fig.savefig(base + ".pdf", metadata={"CreationDate": None, "Producer": None, "Creator": None})
    plt.close(fig)
    print("wrote %s.{png,pdf} (%.2f x %.2f in)" % (base, w, h))


def plain_log_ticks(*axes_):
    """Log-axis tick labels as plain numbers (0.1, 10, 1 000, 100 000: thin-space thousands)
    instead of powers of ten, whose superscripts would print below 7 pt."""
    from matplotlib.ticker import FuncFormatter, NullFormatter

    def show(v, _pos=None):
        if v >= 1000:
            return format(v, ",.0f").replace(",", "\u2009")
        return "%g" % v
    for axis in axes_:
        axis.set_major_formatter(FuncFormatter(show))
        axis.set_minor_formatter(NullFormatter())


def luminance(rgba):
    """Relative luminance (WCAG) of an sRGB colour."""
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgba[:3]]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def text_colour(rgba):
    """Black or white, whichever contrasts more with a background of colour rgba (black when the
    luminance is above 0.179, where the two contrast ratios are equal)."""
    return "black" if luminance(rgba) > 0.179 else "white"


def heatmap(ax, m, xlabels, ylabels, title, outlined=(), cmap="viridis", fmt="%.2g", cap=None, cap_text=None):
    """A matrix as a heat map (perceptually uniform colour map) with its values written in black
    or white according to the luminance of each cell's colour; `outlined` cells (x, y) get a
    frame (black inside white, visible on any colour). Values above `cap` (runs that blew up) do
    not stretch the scale: their cells are vermilion, labelled `cap_text`. Missing values: grey,
    "n/a". Returns the image (for a colour bar)."""
    import copy
    import numpy as np
    from matplotlib import colormaps
    from matplotlib.patches import Rectangle
    a = np.array(m, dtype=float)
    shown = a[np.isfinite(a) & (a <= cap if cap is not None else True)]
    cm = copy.copy(colormaps[cmap])
    cm.set_bad("#dddddd")
    cm.set_over("#D55E00")
    im = ax.imshow(np.ma.masked_invalid(a), origin="lower", aspect="auto", cmap=cm,
                   vmin=shown.min() if shown.size else None, vmax=shown.max() if shown.size else None)
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            v = a[i, j]
            if not np.isfinite(v):
                ax.text(j, i, "n/a", ha="center", va="center", fontsize=SMALL, color="black")
            elif cap is not None and v > cap:
                ax.text(j, i, cap_text or (">" + fmt % cap), ha="center", va="center", fontsize=SMALL,
                        color=text_colour(cm.get_over()))
            else:
                ax.text(j, i, fmt % v, ha="center", va="center", fontsize=SMALL, color=text_colour(cm(im.norm(v))))
    for j, i in outlined:
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="white", lw=2.4, zorder=3))
        ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, ec="black", lw=1.0, zorder=4))
    ax.set_xticks(range(len(xlabels)))
    ax.set_xticklabels(xlabels, rotation=45, ha="right", rotation_mode="anchor")
    ax.set_yticks(range(len(ylabels)))
    ax.set_yticklabels(ylabels)
    ax.tick_params(length=0)
    ax.set_title(title)
    return im


def place_labels(ax, points, labels, avoid=(), lines=(), fontsize=SMALL, radius=5.0):
    """Writes labels[k] next to points[k] (data coordinates) where it overlaps neither a label
    already placed, nor a marker (points and `avoid`), nor a line (`lines`: polylines in data
    coordinates), nor the axes' edge. Candidates: 8 directions at growing distances; the free one
    of least cost wins (farther costs more, and so does a place nearer to another labelled point
    than to its own, which would read as that point's label); a thin leader line when it is not
    the nearest ring. Call it after the axes' limits and scales are final."""
    import numpy as np
    fig = ax.figure
    fig.canvas.draw()
    px = fig.dpi / 72.0
    tr = ax.transData
    box = ax.get_window_extent()
    own = [tr.transform(p) for p in points]
    marks = own + [tr.transform(p) for p in avoid]
    mr = 3.5 * px  # half size of a marker, pixels
    taken = [(x - mr, y - mr, x + mr, y + mr) for x, y in marks]
    lw = 1.0 * px
    for line in lines:
        d = [tr.transform(p) for p in line]
        for (x0, y0), (x1, y1) in zip(d[:-1], d[1:]):
            n = max(1, int(math.hypot(x1 - x0, y1 - y0) / (2 * px)))
            for k in range(n + 1):
                x, y = x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n
                taken.append((x - lw, y - lw, x + lw, y + lw))
    dirs = [(0, -1), (-1, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (1, 1), (0, 1)]
    rings = (1.0, 1.8, 2.8, 4.0, 5.5, 7.5)
    for k, ((x, y), text) in enumerate(zip(own, labels)):
        w = (0.62 * fontsize * len(text) + 2) * px
        h = (fontsize + 1) * px
        best = None
        for ri, ring in enumerate(rings):
            for di, (dx, dy) in enumerate(dirs):
                n = math.hypot(dx, dy)
                cx = x + dx / n * radius * ring * px + dx * w / 2
                cy = y + dy / n * radius * ring * px + dy * h / 2
                b = (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2)
                if not (b[0] >= box.x0 and b[2] <= box.x1 and b[1] >= box.y0 and b[3] <= box.y1):
                    continue
                if any(b[0] < t[2] and t[0] < b[2] and b[1] < t[3] and t[1] < b[3] for t in taken):
                    continue
                mine = math.hypot(cx - x, cy - y)
                misread = any(math.hypot(cx - ox, cy - oy) < mine for j, (ox, oy) in enumerate(own) if j != k)
                cost = 3.0 * ri + 0.1 * di + (10.0 if misread else 0.0)
                if best is None or cost < best[0]:
                    best = (cost, cx, cy, b, ring)
        if best is None:  # no free place: the nearest one
            cx, cy = x + radius * px + w / 2, y + radius * px + h / 2
            best = (0.0, cx, cy, (cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2), 1.0)
        _, cx, cy, b, ring = best
        taken.append(b)
        ann = ax.annotate(text, xy=tuple(np.asarray(tr.inverted().transform((x, y)))),
                          xytext=((cx - x) / px, (cy - y) / px), textcoords="offset points", ha="center",
                          va="center", fontsize=fontsize, zorder=6,
                          arrowprops=(dict(arrowstyle="-", lw=0.4, color="0.3", shrinkA=0, shrinkB=2.5)
                                      if ring > 1.0 else None))
        ann.set_in_layout(False)
