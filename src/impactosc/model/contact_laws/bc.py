"""Model BC's own law, the paper's: the family itself, b, n2 and n3 as given."""

from __future__ import annotations

from impactosc.model.contact_laws.component import ContactLaw, Surface


class BC(ContactLaw):
    name = "bc"
    force = "kI (h^n1 + b h^n2 sgn(v) |v|^n3), 0 where the bracket is negative"
    reads_damping = True
    surfaces = (
        Surface(
            "cut",
            "h^n1 + b h^n2 sgn(v) |v|^n3 (with n2 = n1: v + b^(-1/n3))",
            "the bracket turns negative: F = 0 past it (with n2 = n1 the line v = -b^(-1/n3))",
        ),
    )


LAW = BC()
