"""bodyplay.testing"""
