"""bodyplay.events"""
