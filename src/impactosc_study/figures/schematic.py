"""Fig. 1: schematic of the rig with the symbols of model BC (paper eq. 1).

Why drawn here: the paper's Fig. 1 is a photograph-based drawing from Kudra et al. (2018)
that is not available; a reader needs a figure that maps every symbol of eq. (1) to a part
of the hardware: cart of mass m on a guide, springs k, damper c, dry friction T in the
linear bearing, rotating unbalance m0 e at angle phi = w t, obstacle at x = xI with the
Hunt-Crossley contact (kI, b, n1, n2, n3), coordinate x.
"""

from __future__ import annotations

import numpy as np
from matplotlib import pyplot as plt
from matplotlib.patches import Arc, Circle, FancyArrowPatch, Polygon, Rectangle, Wedge

from impactosc_study.figures.style import DOUBLE, apply_style

__all__ = ["fig01_rig"]

INK = "0.1"


def _hatch(ax, x0, x1, y, side=-1, n=None, length=0.3):
    """Ground hatching below (side=-1) a horizontal line from x0 to x1 at height y."""
    n = n or max(int((x1 - x0) / 0.3), 2)
    for xs in np.linspace(x0, x1, n):
        ax.plot([xs, xs - length], [y, y + side * length], color=INK, lw=0.6)
    ax.plot([x0, x1], [y, y], color=INK, lw=1.0)


def _vhatch(ax, x, y0, y1, side=-1, length=0.3):
    """Wall hatching on one side of a vertical line at x."""
    for ys in np.linspace(y0, y1, max(int((y1 - y0) / 0.3), 2)):
        ax.plot([x, x + side * length], [ys, ys - length], color=INK, lw=0.6)
    ax.plot([x, x], [y0, y1], color=INK, lw=1.0)


def _spring(ax, x0, x1, y, n=7, amp=0.18, lead=0.35, lw=0.9):
    """Zig-zag spring between (x0, y) and (x1, y)."""
    xs = np.linspace(x0 + lead, x1 - lead, 2 * n + 1)
    ys = y + amp * np.array([0] + [(-1) ** k for k in range(2 * n - 1)] + [0])
    ax.plot(np.r_[x0, xs, x1], np.r_[y, ys, y], color=INK, lw=lw)


def _damper(ax, x0, x1, y, w=0.22, lw=0.9):
    """Dashpot between (x0, y) and (x1, y): cylinder open to the right, piston from the right."""
    xm = 0.5 * (x0 + x1)
    c0, c1 = xm - 0.45, xm + 0.25
    ax.plot([x0, c0], [y, y], color=INK, lw=lw)
    ax.plot([c0, c0, c1], [y - w, y + w, y + w], color=INK, lw=lw)
    ax.plot([c0, c1], [y - w, y - w], color=INK, lw=lw)
    ax.plot([xm, xm], [y - 0.7 * w, y + 0.7 * w], color=INK, lw=lw + 0.4)
    ax.plot([xm, x1], [y, y], color=INK, lw=lw)


def _dim_arrow(ax, x0, x1, y, text, dy=0.12, color=INK, fs=8):
    ax.add_patch(FancyArrowPatch((x0, y), (x1, y), arrowstyle="->", mutation_scale=8, lw=0.8, color=color))
    ax.text(0.5 * (x0 + x1), y + dy, text, ha="center", va="bottom", fontsize=fs, color=color)


def _draw_unbalance(ax, cart_x0, cart_y0, cart_y1):
    """The rotating unbalance on the cart (disk, arm at phi from the vertical, mass m0 at
    radius e) and the force it exerts."""
    cx, cy, r = 8.0, cart_y0 + 1.3, 0.82
    ax.add_patch(Circle((cx, cy), r, fc="white", ec=INK, lw=0.9))
    ax.plot([cx, cx], [cy, cy + r + 0.35], color="0.4", lw=0.6, ls="--")
    phi = np.deg2rad(50.0)  # from the vertical towards +x: x-force m0 e w^2 sin(phi)
    mx, my = cx + r * 0.8 * np.sin(phi), cy + r * 0.8 * np.cos(phi)
    ax.plot([cx, mx], [cy, my], color=INK, lw=1.1)
    ax.add_patch(Circle((mx, my), 0.13, fc=INK, ec=INK))
    ax.add_patch(Circle((cx, cy), 0.05, fc=INK, ec=INK))
    ax.text(mx + 0.17, my + 0.05, "$m_0$", fontsize=8, ha="left", va="bottom")
    ax.text(cx + 0.5 * (mx - cx) + 0.12, cy + 0.5 * (my - cy) - 0.18, "$e$", fontsize=8, ha="left", va="center")
    ax.add_patch(Arc((cx, cy), 0.75, 0.75, theta1=90 - np.rad2deg(phi), theta2=90, lw=0.7, color="tab:blue"))
    ax.text(cx + 0.12, cy + 0.5, r"$\varphi$", fontsize=8, color="tab:blue", ha="left", va="bottom")
    ax.add_patch(
        FancyArrowPatch(
            (cx - 0.62, cy - 0.72),
            (cx + 0.62, cy - 0.72),
            connectionstyle="arc3,rad=0.45",
            arrowstyle="->",
            mutation_scale=7,
            lw=0.7,
            color="tab:blue",
        )
    )
    ax.text(cx, cy - r - 0.12, r"$\omega = \dot\varphi$", fontsize=7.5, color="tab:blue", ha="center", va="top")
    _dim_arrow(ax, cart_x0 + 0.6, cart_x0 + 2.1, cart_y1 + 0.15, r"$m_0 e\,\omega^2 \sin\varphi$", color="tab:blue")


def _draw_obstacle(ax, ground, cart_x1, cart_y0):
    """The bumper of the cart and the obstacle with its Hunt-Crossley contact; returns the
    bumper's tip, the contact face (x = xI) and the bumper's height."""
    by = cart_y0 + 1.3
    ax.add_patch(Wedge((cart_x1, by), 0.35, -90, 90, fc="0.6", ec=INK, lw=0.8))
    tip = cart_x1 + 0.35
    face = 11.25  # contact face x = xI
    block0, block1 = 12.4, 13.3
    ax.add_patch(Rectangle((block0, ground), block1 - block0, 3.3, fc="0.8", ec=INK, lw=1.0, hatch="///"))
    ax.text(block1 + 0.12, ground + 3.15, "obstacle\n(support)", fontsize=7, ha="left", va="top")
    ax.add_patch(
        Polygon(
            [[face, by - 0.55], [face + 0.12, by - 0.55], [face + 0.12, by + 0.55], [face, by + 0.55]],
            closed=True,
            fc="0.6",
            ec=INK,
            lw=0.8,
        )
    )
    _spring(ax, face + 0.12, block0, by + 0.3, n=4, amp=0.1, lead=0.15, lw=0.8)
    _damper(ax, face + 0.12, block0, by - 0.3, w=0.12, lw=0.8)
    ax.text(0.5 * (face + block0), by + 0.62, r"$k_I,\ b$", fontsize=8, ha="center", va="bottom")
    ax.text(
        block1 + 0.12,
        by - 0.05,
        r"contact when $x \geq x_I$:"
        "\n"
        r"$F_I = k_I\,(h^{n_1} + b\,h^{n_2}\,\mathrm{sgn}\,\dot x\,|\dot x|^{n_3})$,"
        "\n"
        r"$h = x - x_I$ (Hunt–Crossley)",
        fontsize=6.8,
        ha="left",
        va="center",
    )
    return tip, face, by


def _draw_axis(ax, tip, face, by):
    """The coordinate axis: current position x, obstacle face xI, relaxed springs x = 0."""
    ya = 5.45
    ax.add_patch(FancyArrowPatch((6.4, ya), (14.4, ya), arrowstyle="->", mutation_scale=9, lw=0.8, color=INK))
    ax.text(14.5, ya, "$x$", fontsize=9, va="center", ha="left")
    zero = face + 0.75
    for xt, lab in ((tip, "$x$"), (face, "$x_I$"), (zero, "$0$")):
        ax.plot([xt, xt], [ya - 0.1, ya + 0.1], color=INK, lw=0.8)
        ax.text(xt, ya + 0.16, lab, fontsize=8, ha="center", va="bottom")
    ax.plot([tip, tip], [by, ya - 0.1], color="0.45", lw=0.5, ls="--")
    ax.plot([face, face], [by + 0.55, ya - 0.1], color="0.45", lw=0.5, ls="--")
    ax.plot([zero, zero], [by + 1.0, ya - 0.1], color="0.45", lw=0.5, ls=":")
    ax.text(
        zero + 0.15,
        ya - 0.2,
        r"springs relaxed at $x = 0$;"
        "\n"
        r"$x_I = -2.086$ mm $< 0$: at rest the"
        "\n"
        r"cart is pressed against the obstacle",
        fontsize=6.5,
        ha="left",
        va="top",
        color="0.3",
    )


def fig01_rig():
    """The rig of Kudra et al. (2018) as model BC sees it; returns the Figure."""
    apply_style()
    fig, ax = plt.subplots(figsize=(DOUBLE, 7.4 / 2.54))
    ax.set_xlim(0, 17)
    ax.set_ylim(-0.2, 6.6)
    ax.set_aspect("equal")
    ax.axis("off")

    ground = 1.0
    _hatch(ax, 0.6, 16.0, ground)
    _vhatch(ax, 1.0, ground, 5.0)  # left support

    # guide with linear ball bearing
    ax.add_patch(Rectangle((2.6, ground), 9.6, 0.28, fc="0.85", ec=INK, lw=0.8))
    ax.text(3.0, ground + 0.14, "guide", fontsize=6.5, va="center", ha="left", color="0.3")
    cart_x0, cart_x1, cart_y0, cart_y1 = 6.0, 10.0, ground + 0.62, ground + 3.1
    for xb in (6.5, 7.2, 8.8, 9.5):
        ax.add_patch(Circle((xb, ground + 0.45), 0.17, fc="white", ec=INK, lw=0.8))
    ax.add_patch(Rectangle((cart_x0, cart_y0), cart_x1 - cart_x0, cart_y1 - cart_y0, fc="#dfe8f3", ec=INK, lw=1.0))
    ax.text(cart_x0 + 0.12, cart_y1 - 0.1, "cart,\nmass $m$", fontsize=7.5, ha="left", va="top")

    # dry friction in the bearing: opposing arrows at the cart/guide interface
    ax.annotate(
        r"dry friction $T\,\dot x/\sqrt{\dot x^2+\varepsilon^2}$" "\n(linear bearing)",
        xy=(9.5, ground + 0.3),
        xytext=(10.4, 0.5),
        fontsize=7,
        ha="left",
        va="top",
        bbox=dict(fc="white", ec="none", pad=0.3),
        arrowprops=dict(arrowstyle="-", lw=0.6, color="0.3", shrinkA=0, shrinkB=2),
    )

    # springs k and damper c from the support to the cart
    _spring(ax, 1.0, cart_x0, cart_y0 + 1.85)
    ax.text(3.5, cart_y0 + 2.2, "$k$", fontsize=9, ha="center", va="bottom")
    _damper(ax, 1.0, cart_x0, cart_y0 + 0.75)
    ax.text(3.35, cart_y0 + 0.35, "$c$", fontsize=9, ha="center", va="top")

    _draw_unbalance(ax, cart_x0, cart_y0, cart_y1)

    tip, face, by = _draw_obstacle(ax, ground, cart_x1, cart_y0)

    _draw_axis(ax, tip, face, by)
    ax.text(
        0.6,
        6.35,
        r"$m\ddot x + kx + c\dot x + T\dot x/\sqrt{\dot x^2+\varepsilon^2} + F_I(x,\dot x)"
        r" = m_0 e\,\omega^2\sin\varphi,\quad \varphi = \omega t$",
        fontsize=8,
        ha="left",
        va="center",
    )
    return fig
