"""Results for people: summary tables beside the study's numbers (summary, summary_files, study),
the files `dvc plots show` reads (dvcplots), the study's figures (figures), loading evaluation
results (results) and the self-contained HTML report (report, html, sections, examples). May import
evaluation, models, data, params and the foundation modules; only ablations import it.
"""
