"""bodyplay.record"""
