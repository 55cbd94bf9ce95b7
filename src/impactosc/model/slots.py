"""Where each number sits in the parameter array ``p`` that the numba core reads.

Why a module of its own: the model's parameters (:mod:`impactosc.model.parameters`), the contact
laws' compiled force (:mod:`impactosc.model.contact_laws.kernel`) and the core all index ``p``;
this leaf imports nothing, so each of them may import it.
"""

# --- index into the parameter array p (ModelParams.as_array) --------------------------------
# Model BC's twelve parameters, in the order of impactosc.model.parameters.PARAMETERS; the
# contact law's index in contact_laws.LAWS (for Python code that holds only an array: the core
# never reads it); the family numbers a law places beside b, n2, n3 (contact_laws.component); w;
# then from P_OWN on the laws' own parameters, in the order of contact_laws.OWN_PARAMETERS.
(
    P_M,
    P_M0E,
    P_K,
    P_C,
    P_T,
    P_EPS,
    P_KI,
    P_B,  # the family's damping factor b (a restitution law's: this contact's chi, set at its onset)
    P_N1,
    P_N2,
    P_N3,
    P_XI,
    P_LAW,
    P_CHI,  # a damping set per contact, b = chi = P_CHI / (P_CHI_PER * v0) (a restitution law's g(e) ...
    P_CHI_PER,  # ... as a fraction, as it is written: the same bits as the published form); P_CHI = 0: b as placed
    P_H1,  # depth of a surface inside the contact, h = h1, behind which ...
    P_K2,  # ... a second stop adds k2 (h - h1)^n1 (inf and 0: no such surface)
    P_OMEGA,
) = range(18)
P_OWN = 18
