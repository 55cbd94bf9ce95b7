# The contact laws beside model BC's (beyond the paper): how closely each restitution law's free
# impact delivers the coefficient of restitution it is built for (impactosc.dynamics.restitution),
# against the nominal e at a typical impact velocity and against v0. Target: restitution.

RESTITUTION_TABLE = study_path("tables/restitution.csv")


rule restitution:
    input:
        cache=NUMBA_CACHE,
    output:
        table=RESTITUTION_TABLE,
        md=study_path("tables/restitution.md"),
        png=report(
            supplementary("contact_laws", "restitution")[0],
            caption="../report/restitution.rst",
            category="Contact laws",
        ),
        pdf=supplementary("contact_laws", "restitution")[1],
    log:
        logs("contact_laws/restitution"),
    benchmark:
        benchmarks("contact_laws/restitution")
    params:
        model=config["model"],
        e=[0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95],
        v0_table=0.2,
        v0=[0.001, 0.01, 0.1, 0.2, 1.0],
        e_v0=0.7,
    script:
        "../scripts/restitution.py"


tier_products("beyond", rules.restitution.output)
tier_jobs("beyond", rules.restitution)
