"""Where each number sits in the parameter array ``p`` that the numba core reads.

Why a module of its own: the model's parameters (:mod:`impactosc.model.parameters`), the contact
laws' compiled force (:mod:`impactosc.model.contact_laws.kernel`) and the core all index ``p``;
this leaf imports nothing, so each of them may import it.
"""

# --- index into the parameter array p (ModelParams.as_array): PARAMETERS, then w -----------
# then the law's code, e and cI, and w (P_B, P_N2, P_N3 hold the law's place in model BC's family;
# a restitution law's P_B is set at each contact's onset by the core)
(P_M, P_M0E, P_K, P_C, P_T, P_EPS, P_KI, P_B, P_N1, P_N2, P_N3, P_XI, P_LAW, P_E, P_CI, P_OMEGA) = range(16)
N_PARAMS = 16
