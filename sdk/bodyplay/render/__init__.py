"""bodyplay.render"""
