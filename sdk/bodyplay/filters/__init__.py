"""bodyplay.filters"""
