# The table of every number the paper states next to ours, merged from the figure groups.


rule paper_vs_replication:
    input:
        rows=lambda wc: TABLE_ROWS,
    output:
        csv="results/tables/paper_vs_replication.csv",
        md="results/tables/paper_vs_replication.md",
    log:
        "results/logs/paper_vs_replication.log",
    conda:
        "../envs/impactosc.yaml"
    script:
        "../scripts/paper_vs_replication.py"
