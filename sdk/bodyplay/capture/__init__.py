"""bodyplay.capture"""
